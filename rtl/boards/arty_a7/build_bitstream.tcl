# The bitstream of ts_arty_top for the Digilent Arty A7-100T (xc7a100tcsg324-1), in Vivado's non-project mode, as one
# command from the repository's root (docs/board.md):
#
#   vivado -mode batch -source rtl/boards/arty_a7/build_bitstream.tcl -tclargs standalone
#   vivado -mode batch -source rtl/boards/arty_a7/build_bitstream.tcl -tclargs spi
#
# standalone: the devkit without a microcontroller (STANDALONE = 1), its worlds the ROM image ts_arty_rom.mem beside
# this script (write another with `tripsitter rom -o rtl/boards/arty_a7/ts_arty_rom.mem ...`); spi: the board with the
# microcontroller on Pmod JD (STANDALONE = 0). A second argument names the output folder (default
# build/vivado/arty-MODE/): the bitstream ts_arty_MODE.bit, the reports timing.rpt and utilization.rpt, and the
# checkpoint after routing. Not run where this was written (no Vivado there): Yosys's figures are in docs/measured.md.
set here [file dirname [file normalize [info script]]]
set root [file normalize [file join $here .. .. ..]]

set mode standalone
if {$argc >= 1} { set mode [lindex $argv 0] }
switch -- $mode {
  standalone { set standalone 1 }
  spi        { set standalone 0 }
  default    { puts stderr "build_bitstream.tcl: MODE is standalone or spi, not '$mode'"; exit 2 }
}
set out [file join $root build vivado arty-$mode]
if {$argc >= 2} { set out [file normalize [lindex $argv 1]] }
file mkdir $out

# The sources: every package first (blocks name ts_artix_pkg::X and ts_link_pkg::X), then every file of the folders
# the top takes blocks from: the artix device's, the receiver's and VGA blocks it shares with ts_device, the board's
# blocks and the top. Modules the top does not instantiate are read and left out by synthesis. (scripts/synth.sh arty
# reads the same modules for Yosys, from the artix device's list of files.)
set sources [lsort [glob [file join $root rtl * ts_*_pkg.sv]]]
foreach dir {artix receiver vga boards boards/arty_a7} {
  foreach f [lsort [glob -nocomplain [file join $root rtl $dir ts_*.sv]]] {
    if {[lsearch -exact $sources $f] < 0} { lappend sources $f }
  }
}
read_verilog -sv $sources
# The ROM image, found by its name (ts_arty_top's ROM_FILE) when synthesis initialises the ROM host's block RAM.
read_mem [file join $here ts_arty_rom.mem]
read_xdc [file join $here ts_arty_a7.xdc]

synth_design -top ts_arty_top -part xc7a100tcsg324-1 -generic STANDALONE=$standalone
opt_design
place_design
route_design
write_checkpoint -force [file join $out ts_arty_$mode.dcp]
report_timing_summary -file [file join $out timing.rpt]
report_utilization -file [file join $out utilization.rpt]
write_bitstream -force [file join $out ts_arty_$mode.bit]

# The clock's worst setup slack: the datapath is designed for 100 MHz, and this is where a vendor timing run says
# whether it makes it.
set worst [get_timing_paths -max_paths 1 -nworst 1 -setup]
set slack [get_property SLACK $worst]
puts "ts_arty_top ($mode): worst setup slack $slack ns at 100 MHz; bitstream [file join $out ts_arty_$mode.bit]"
if {$slack < 0} {
  puts "ts_arty_top ($mode): timing NOT met: see [file join $out timing.rpt]; the bitstream may misbehave on the board"
}
