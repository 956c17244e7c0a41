// ts_arty_top: the artix device (rtl/artix/ts_artix_device.sv) on a Digilent Arty A7-100T (XC7A100T-1CSG324) with a
// Digilent Pmod VGA, the report's "A-100T devkit" with its "VGA PMOD" (its section 5). Pins and I/O standards are in
// ts_arty_a7.xdc; docs/rtl.md, "The board", draws the blocks and gives the microcontroller's wiring.
//
// Two builds of one top, chosen by STANDALONE:
//   1  the devkit as the report's section 5 ran it, without a microcontroller: a ROM host (ts_rom_host) plays the
//      worlds of a camera path, written by `tripsitter rom` into ROM_FILE, into the device's SPI pins; BTN0 steps to
//      the next world, BTN1 back to the one before. The device speaks wire v2, on which every intact world is shown
//      (a ROM sends the same numbered frames again and again, which wire v3 refuses as replays).
//   0  the board of the report's section 6: the microcontroller's SPI (SCLK, MOSI, CS_N in, READY out) on Pmod JD,
//      wire v3 (docs/link_format.md). The buttons are not used.
// Both: the 100 MHz oscillator is the device's clock (it is designed for it: 4 clocks a pixel); the RESET button
// (active low) and the configuration reset it (ts_reset_sync); the Pmod VGA on JB and JC carries the 4 + 4 + 4
// colour bits and the two syncs straight from the device's registers; LD4..LD7 show the receiver's counters:
//   led[1:0]  worlds accepted, the count's two low bits (each accepted world changes them)
//   led[2]    frames rejected, the count's low bit (each damaged or refused frame toggles it)
//   led[3]    something was refused since reset: a rejected frame, a replayed world or a run of garbage bytes
module ts_arty_top #(
    parameter int STANDALONE = 1,
    parameter int N = 9,                        // sphere units (the artix preset: 9)
    parameter ROM_FILE = "ts_arty_rom.mem",     // STANDALONE: the ROM image ($readmemh), as `tripsitter rom` writes it
    parameter int ROM_BYTES = 8192,             // STANDALONE: its block RAM (host::kBoardRomBytes)
    parameter int DEBOUNCE_CYCLES = 1_000_000,  // a button's level must hold this long to count: 10 ms
    parameter int RESET_CYCLES = 16,            // clocks the reset outlasts the button and the configuration
    parameter int SPI_HALF_CYCLES = 5           // STANDALONE: the ROM host's SCLK half period, 5: 10 MHz
) (
    input  logic       clk,        // the 100 MHz oscillator
    input  logic       rst_btn_n,  // the RESET button, low while pressed
    input  logic [3:0] btn,        // BTN0..BTN3, high while pressed
    output logic [3:0] led,        // LD4..LD7
    // Pmod VGA (J1 on JB, J2 on JC).
    output logic [3:0] vga_r,
    output logic [3:0] vga_g,
    output logic [3:0] vga_b,
    output logic       vga_hs_n,
    output logic       vga_vs_n,
    // The microcontroller on Pmod JD (STANDALONE = 0; not used otherwise).
    input  logic       pmod_sclk,
    input  logic       pmod_mosi,
    input  logic       pmod_cs_n,
    output logic       pmod_ready
);
  localparam int CntW = 32;  // as ts_receiver's checks are wide; the LEDs show low bits

  logic rst;
  ts_reset_sync #(.HOLD_CYCLES(RESET_CYCLES)) reset (.clk, .btn_n(rst_btn_n), .rst);

  // ---- the device's SPI pins: the ROM host's or the microcontroller's -------------------------------------------
  logic spi_sclk, spi_mosi, spi_cs_n, spi_ready, receiver_idle;
  logic unused_buttons;
  if (STANDALONE != 0) begin : g_rom
    logic next, prev;
    ts_debounce #(.STABLE_CYCLES(DEBOUNCE_CYCLES)) next_button (.clk, .rst, .btn(btn[0]), .pressed(next));
    ts_debounce #(.STABLE_CYCLES(DEBOUNCE_CYCLES)) prev_button (.clk, .rst, .btn(btn[1]), .pressed(prev));
    logic [$clog2(ROM_BYTES)-1:0] unused_world;
    ts_rom_host #(.ROM_FILE(ROM_FILE), .ROM_BYTES(ROM_BYTES), .HALF_CYCLES(SPI_HALF_CYCLES)) host (
        .clk, .rst, .next, .prev, .ready(spi_ready), .idle(receiver_idle),
        .sclk(spi_sclk), .mosi(spi_mosi), .cs_n(spi_cs_n), .world(unused_world)
    );
    assign pmod_ready = 1'b0;
    assign unused_buttons = ^{btn[3:2], pmod_sclk, pmod_mosi, pmod_cs_n};
  end else begin : g_pmod
    assign spi_sclk = pmod_sclk;
    assign spi_mosi = pmod_mosi;
    assign spi_cs_n = pmod_cs_n;
    assign pmod_ready = spi_ready;
    assign unused_buttons = ^{btn, receiver_idle};
  end

  // ---- the device ------------------------------------------------------------------------------------------------
  logic            unused_strobe, unused_shown_valid, unused_late_valid;
  logic [9:0]      unused_line, unused_column, unused_late_pixels;
  logic [31:0]     unused_shown_sequence;
  logic [CntW-1:0] accepted, rejected, garbage, replayed;
  logic [CntW-1:0] unused_replaced, unused_dropped, unused_missing, unused_sessions;
  ts_artix_device #(.N(N), .WIRE(STANDALONE != 0 ? 2 : 3), .CNT_W(CntW)) device (
      .clk, .rst,
      .spi_sclk, .spi_mosi, .spi_cs_n, .spi_ready, .end_of_stream(1'b0),
      .vga_r, .vga_g, .vga_b, .vga_hsync_n(vga_hs_n), .vga_vsync_n(vga_vs_n),
      .vga_strobe(unused_strobe), .beam_line(unused_line), .beam_column(unused_column), .receiver_idle,
      .worlds_accepted(accepted), .worlds_replaced(unused_replaced), .frames_rejected(rejected),
      .garbage_runs(garbage), .bytes_dropped(unused_dropped), .worlds_missing(unused_missing),
      .worlds_replayed(replayed), .sessions(unused_sessions),
      .shown_valid(unused_shown_valid), .shown_sequence(unused_shown_sequence),
      .late_valid(unused_late_valid), .late_pixels(unused_late_pixels)
  );

  // ---- the LEDs --------------------------------------------------------------------------------------------------
  logic refused_q;
  wire unused_high_counts = ^{accepted[CntW-1:2], rejected[CntW-1:1]};
  always_ff @(posedge clk) begin
    if (rst) refused_q <= 1'b0;
    else if (rejected != '0 || replayed != '0 || garbage != '0) refused_q <= 1'b1;
  end
  assign led = {refused_q, rejected[0], accepted[1:0]};
endmodule
