// ts_vga_timing: the VGA block. Two counters (column 0..799, line 0..524) driven by the mode's porch and sync
// widths, advanced once per pixel clock; the pixel clock is an enable, every 4th cycle of the 100 MHz device clock
// (25 MHz, as the board made it). It reads the front line buffer once per visible column and drives the
// connector: RGB444, active-low hsync and vsync, all registered, black outside the visible area.
//
// C++ model: src/tripsitter/device/vga.h/.cpp (VgaTimingGenerator) with vga_signal.h (VgaMode: 640 + 16 + 96 + 48
// columns, 480 + 10 + 2 + 33 lines; VgaSample), and Device::tick in device.cpp: one pixel clock is four device
// cycles (kCyclesPerPixelClock), and the device comes out of reset at the start of vertical blanking, line 480,
// column 0, so the first whole frame it sends is the first one after reset.
//
// Time inside a pixel clock. `phase` counts its four device cycles; the counters change after phase 3 (`pix_en`).
//   phase 0  the line buffer is asked for the pixel of `column` (rd_en, columns 0..639 of every line);
//   phase 1  its colour arrives (rd_data, a registered block-RAM read) and the connector's registers take the
//            sample of (line, column): the colour if visible, else black, and the two sync levels;
//   phase 2  the sample is on the pins (vga_strobe marks this cycle) and stays there for four cycles.
// So the pins show the model's sample of pixel clock (line, column) from phase 2 of that pixel clock to phase 1
// of the next: a fixed lag of two device cycles behind the counters, the same for colour and syncs. The line
// buffer is read on every line, blanking lines too, because the read also clears the slot (ts_line_buffers).
//
// line_end marks the last device cycle of a line (column 799, phase 3): the line buffers swap after it, as the
// model swaps them after the line's last sample. frame_start marks the first device cycle of line 480, where the
// model's Device::start_line swaps scene memory; it is high in the first cycle after reset too.
module ts_vga_timing (
    input  logic        clk,
    input  logic        rst,
    // The beam, from the counters.
    output logic [1:0]  phase,        // device cycle within the pixel clock
    output logic [9:0]  column,       // 0..799; 0..639 visible
    output logic [9:0]  line,         // 0..524; 0..479 visible
    output logic        pix_en,       // last cycle of the pixel clock: column (and line) advance after it
    output logic        visible,
    output logic        line_end,     // last cycle of the line: the line buffers swap after it
    output logic        frame_start,  // first cycle of line 480 (vertical blanking)
    // The front line buffer: the pixels of the line, in column order.
    output logic        rd_en,
    input  logic [11:0] rd_data,      // the cycle after rd_en
    // The connector.
    output logic [11:0] vga_rgb,      // RGB444: red 11..8, green 7..4, blue 3..0
    output logic        vga_hsync_n,
    output logic        vga_vsync_n,
    output logic        vga_strobe    // the pins hold a new pixel clock's sample from this cycle on
);
  // 640x480 at 60 Hz (SPEC.md section B, VgaMode).
  localparam int HVisible = 640, HFront = 16, HSync = 96, HBack = 48;
  localparam int VVisible = 480, VFront = 10, VSync = 2, VBack = 33;
  localparam int HTotal = HVisible + HFront + HSync + HBack;  // 800
  localparam int VTotal = VVisible + VFront + VSync + VBack;  // 525
  localparam int HSyncStart = HVisible + HFront;              // 656: the pulse follows the front porch
  localparam int VSyncStart = VVisible + VFront;              // 490

  // The counters. Reset puts the beam where the model's Device starts: line 480, column 0.
  always_ff @(posedge clk) begin
    if (rst) begin
      phase  <= 2'd0;
      column <= 10'd0;
      line   <= 10'(VVisible);
    end else begin
      phase <= phase + 2'd1;
      if (pix_en) begin
        if (column == 10'(HTotal - 1)) begin
          column <= 10'd0;
          line   <= line == 10'(VTotal - 1) ? 10'd0 : line + 10'd1;
        end else begin
          column <= column + 10'd1;
        end
      end
    end
  end

  assign pix_en      = phase == 2'd3;
  assign visible     = column < 10'(HVisible) && line < 10'(VVisible);
  assign line_end    = pix_en && column == 10'(HTotal - 1);
  assign frame_start = phase == 2'd0 && column == 10'd0 && line == 10'(VVisible);
  assign rd_en       = phase == 2'd0 && column < 10'(HVisible);

  // Sync levels of the counters' position (VgaTimingGenerator::hsync_n_at, vsync_n): low during the pulse.
  logic hsync_n, vsync_n;
  assign hsync_n = !(column >= 10'(HSyncStart) && column < 10'(HSyncStart + HSync));
  assign vsync_n = !(line >= 10'(VSyncStart) && line < 10'(VSyncStart + VSync));

  // The connector's registers, loaded at phase 1 when the line buffer's colour has arrived. Their reset values
  // (syncs high, black) are the sample of line 480, column 0, the first one after reset.
  always_ff @(posedge clk) begin
    if (rst) begin
      vga_rgb     <= 12'h000;
      vga_hsync_n <= 1'b1;
      vga_vsync_n <= 1'b1;
      vga_strobe  <= 1'b0;
    end else begin
      vga_strobe <= phase == 2'd1;
      if (phase == 2'd1) begin
        vga_rgb     <= visible ? rd_data : 12'h000;
        vga_hsync_n <= hsync_n;
        vga_vsync_n <= vsync_n;
      end
    end
  end
`ifdef FORMAL
  // Properties (docs/rtl.md, "Proofs"), proven by scripts/prove.sh (proof vga_timing). The periods and widths
  // follow from them: the column steps by one per pixel clock and wraps at 799, the line steps when the column
  // wraps and wraps at 524, so a line is 800 pixel clocks and a frame 525 lines; a sync is low for exactly the
  // columns (lines) of its pulse, so hsync is low 96 pixel clocks a line and vsync 2 lines a frame.
  logic past_valid = 1'b0;
  always_ff @(posedge clk) past_valid <= 1'b1;
  initial assume (rst);

  always_comb begin
    if (past_valid) begin
      p_column_range: assert (column < 10'(HTotal));
      p_line_range: assert (line < 10'(VTotal));
    end
  end
  always_ff @(posedge clk) begin
    if (past_valid && !$past(rst)) begin
      p_phase_steps: assert (phase == $past(phase) + 2'd1);
      // The column advances by one at the end of each pixel clock, from 799 to 0, and holds otherwise.
      if ($past(pix_en)) begin
        p_column_steps: assert (column == ($past(column) == 10'(HTotal - 1) ? 10'd0 : $past(column) + 10'd1));
      end else begin
        p_column_holds: assert (column == $past(column));
      end
      // The line advances when the column wraps, from 524 to 0, and holds otherwise.
      if ($past(line_end)) begin
        p_line_steps: assert (line == ($past(line) == 10'(VTotal - 1) ? 10'd0 : $past(line) + 10'd1));
      end else begin
        p_line_holds: assert (line == $past(line));
      end
      // The pins: from phase 2 on, the sample of the counters' position, registered at phase 1.
      if ($past(phase) == 2'd1) begin
        p_hsync_width: assert (vga_hsync_n == !($past(column) >= 10'(HSyncStart) && $past(column) < 10'(HSyncStart + HSync)));
        p_vsync_width: assert (vga_vsync_n == !($past(line) >= 10'(VSyncStart) && $past(line) < 10'(VSyncStart + VSync)));
        p_black_outside: assert ($past(visible) || vga_rgb == 12'h000);
      end else begin
        p_pins_hold: assert (vga_rgb == $past(vga_rgb) && vga_hsync_n == $past(vga_hsync_n)
                             && vga_vsync_n == $past(vga_vsync_n));
      end
    end
  end
`endif
endmodule
