# Loads a bitstream that build_bitstream.tcl made into the Arty A7-100T on this computer's USB (JTAG through the
# board's FT2232), into the FPGA only: it is gone when the board is powered off.
#
#   vivado -mode batch -source rtl/boards/arty_a7/program_board.tcl \
#          -tclargs build/vivado/arty-standalone/ts_arty_standalone.bit
if {$argc < 1} { puts stderr "program_board.tcl: give the .bit file"; exit 2 }
set bit [file normalize [lindex $argv 0]]
open_hw_manager
connect_hw_server
open_hw_target
set device [lindex [get_hw_devices xc7a100t*] 0]
current_hw_device $device
set_property PROGRAM.FILE $bit $device
program_hw_devices $device
close_hw_manager
puts "programmed $device with $bit"
