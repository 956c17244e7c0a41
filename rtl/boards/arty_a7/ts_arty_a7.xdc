## ts_arty_top (rtl/boards/arty_a7/ts_arty_top.sv) on the Digilent Arty A7-100T, part xc7a100tcsg324-1, with a Digilent
## Pmod VGA on JB and JC and the microcontroller's SPI on JD. Both builds (STANDALONE = 1 and 0) use this one file:
## their ports are the same.
##
## Sources of the pin facts (locations and I/O standards; nothing else is taken from them):
##   - Digilent, Arty-A7-100-Master.xdc, github.com/Digilent/digilent-xdc (read at commit
##     5d2f7792b1b95c7f8af3e9a262ac4c34efeef17b, headed "for the Arty A7-100 Rev. D"; the file on its master branch
##     says "Rev. D and Rev. E"): the oscillator, RESET (ck_rst), BTN0..3, LD4..LD7 and the Pmod headers JB, JC and JD,
##     every one LVCMOS33.
##   - Digilent, Arty Reference Manual (doc 410-319), section 9 "Basic I/O": LD4..LD7 are anode-connected through
##     330-ohm resistors and light when driven high; the RESET button is also the shield connector's RST pin (J7).
##     Not read in a document here, but taken as the board's convention: RESET (ck_rst) reads low while pressed (an
##     active-low reset line) and BTN0..3 read high. Should a board read otherwise, invert rst_btn_n or btn in the top.
##   - Digilent, Pmod VGA Reference Manual (Rev. C board, manual revised January 22, 2018; doc 410-345), "Pinout
##     Description Tables": J1 pins 1-4 R0..R3, 7-10 B0..B3; J2 pins 1-4 G0..G3, 7 HS, 8 VS (9, 10 not connected).
##   - Digilent, Pmod Interface Specification, interface type 2 (SPI): pin 1 CS, 2 MOSI, 3 MISO, 4 SCK. READY takes
##     MISO's pin: the device never answers on SPI.
## A Pmod header's pins 1-4 are the XDC's [0]..[3], pins 7-10 its [4]..[7]; pins 5/11 are ground, 6/12 3.3 V.
##
## If your Pmod VGA sits the other way round (J1 on JC, J2 on JB), swap the JB and JC columns below.

## ---- the 100 MHz oscillator: the device's clock ------------------------------------------------------------------
set_property -dict { PACKAGE_PIN E3  IOSTANDARD LVCMOS33 } [get_ports { clk }]
create_clock -name sys_clk -period 10.000 -waveform {0.000 5.000} [get_ports { clk }]

## ---- RESET (red, active low) and BTN0 (next world), BTN1 (previous world), BTN2, BTN3 (not used) -------------------
set_property -dict { PACKAGE_PIN C2  IOSTANDARD LVCMOS33 } [get_ports { rst_btn_n }]
set_property -dict { PACKAGE_PIN D9  IOSTANDARD LVCMOS33 } [get_ports { btn[0] }]
set_property -dict { PACKAGE_PIN C9  IOSTANDARD LVCMOS33 } [get_ports { btn[1] }]
set_property -dict { PACKAGE_PIN B9  IOSTANDARD LVCMOS33 } [get_ports { btn[2] }]
set_property -dict { PACKAGE_PIN B8  IOSTANDARD LVCMOS33 } [get_ports { btn[3] }]

## ---- LD4..LD7: worlds accepted (2 low bits), frames rejected (low bit), something refused -------------------------
set_property -dict { PACKAGE_PIN H5  IOSTANDARD LVCMOS33 } [get_ports { led[0] }]
set_property -dict { PACKAGE_PIN J5  IOSTANDARD LVCMOS33 } [get_ports { led[1] }]
set_property -dict { PACKAGE_PIN T9  IOSTANDARD LVCMOS33 } [get_ports { led[2] }]
set_property -dict { PACKAGE_PIN T10 IOSTANDARD LVCMOS33 } [get_ports { led[3] }]

## ---- Pmod VGA: J1 on JB (red, blue) -------------------------------------------------------------------------------
set_property -dict { PACKAGE_PIN E15 IOSTANDARD LVCMOS33 } [get_ports { vga_r[0] }]
set_property -dict { PACKAGE_PIN E16 IOSTANDARD LVCMOS33 } [get_ports { vga_r[1] }]
set_property -dict { PACKAGE_PIN D15 IOSTANDARD LVCMOS33 } [get_ports { vga_r[2] }]
set_property -dict { PACKAGE_PIN C15 IOSTANDARD LVCMOS33 } [get_ports { vga_r[3] }]
set_property -dict { PACKAGE_PIN J17 IOSTANDARD LVCMOS33 } [get_ports { vga_b[0] }]
set_property -dict { PACKAGE_PIN J18 IOSTANDARD LVCMOS33 } [get_ports { vga_b[1] }]
set_property -dict { PACKAGE_PIN K15 IOSTANDARD LVCMOS33 } [get_ports { vga_b[2] }]
set_property -dict { PACKAGE_PIN J15 IOSTANDARD LVCMOS33 } [get_ports { vga_b[3] }]

## ---- Pmod VGA: J2 on JC (green, syncs) ----------------------------------------------------------------------------
set_property -dict { PACKAGE_PIN U12 IOSTANDARD LVCMOS33 } [get_ports { vga_g[0] }]
set_property -dict { PACKAGE_PIN V12 IOSTANDARD LVCMOS33 } [get_ports { vga_g[1] }]
set_property -dict { PACKAGE_PIN V10 IOSTANDARD LVCMOS33 } [get_ports { vga_g[2] }]
set_property -dict { PACKAGE_PIN V11 IOSTANDARD LVCMOS33 } [get_ports { vga_g[3] }]
set_property -dict { PACKAGE_PIN U14 IOSTANDARD LVCMOS33 } [get_ports { vga_hs_n }]
set_property -dict { PACKAGE_PIN V14 IOSTANDARD LVCMOS33 } [get_ports { vga_vs_n }]

## ---- the microcontroller on JD: JD1 CS_N, JD2 MOSI, JD3 READY, JD4 SCLK (SPI mode 0) -------------------------------
## Pulled to their idle levels (deselected, clock low), so that a board with nothing on JD sees no transfer.
set_property -dict { PACKAGE_PIN D4  IOSTANDARD LVCMOS33 PULLUP   TRUE } [get_ports { pmod_cs_n }]
set_property -dict { PACKAGE_PIN D3  IOSTANDARD LVCMOS33 PULLDOWN TRUE } [get_ports { pmod_mosi }]
set_property -dict { PACKAGE_PIN F4  IOSTANDARD LVCMOS33 } [get_ports { pmod_ready }]
set_property -dict { PACKAGE_PIN F3  IOSTANDARD LVCMOS33 PULLDOWN TRUE } [get_ports { pmod_sclk }]

## ---- timing -------------------------------------------------------------------------------------------------------
## The SPI inputs, the buttons and RESET change whenever their source likes: there is no clock they are timed
## against. Each passes a two-flop synchroniser before any logic uses it (ts_spi_rx: SCLK, MOSI and CS_N through
## synchronisers of equal depth, so a MOSI bit is used in the same clock as the SCLK edge it was stable around, which
## wants SCLK at most clk/8, 12.5 MHz: docs/rtl.md, "The board"; ts_debounce, ts_reset_sync). So no input delay
## means anything; they are false paths.
set_false_path -from [get_ports { pmod_sclk pmod_mosi pmod_cs_n rst_btn_n btn[*] }]
## The outputs are driven from registers and read by nothing that shares the clock: the Pmod VGA's resistor ladders
## and the monitor (a pixel holds for 4 clocks, 40 ns), the LEDs, and READY, which the microcontroller samples
## before it starts a world. No output delay means anything either.
set_false_path -to [get_ports { vga_r[*] vga_g[*] vga_b[*] vga_hs_n vga_vs_n led[*] pmod_ready }]
## The synchronisers' first flip-flops: placed next to their second, as Vivado does for ASYNC_REG cells. The names
## are those the RTL gives them (ts_spi_rx's sclk_q, mosi_q, csn_q; the debouncers' and the reset's btn_q); -quiet:
## a name Vivado elaborates differently gives an empty list, not an error.
set_property ASYNC_REG TRUE [get_cells -quiet -hierarchical -filter {NAME =~ *spi/sclk_q_reg*}]
set_property ASYNC_REG TRUE [get_cells -quiet -hierarchical -filter {NAME =~ *spi/mosi_q_reg*}]
set_property ASYNC_REG TRUE [get_cells -quiet -hierarchical -filter {NAME =~ *spi/csn_q_reg*}]
set_property ASYNC_REG TRUE [get_cells -quiet -hierarchical -filter {NAME =~ *btn_q_reg*}]

## ---- configuration: bank 0 at 3.3 V, as on the Arty A7 ------------------------------------------------------------
set_property CFGBVS VCCO [current_design]
set_property CONFIG_VOLTAGE 3.3 [current_design]
