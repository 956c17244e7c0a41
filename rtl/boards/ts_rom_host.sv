// ts_rom_host: the host of a board without its microcontroller (the report's devkit set-up, its section 5): the
// worlds of a camera path, encoded by the host program (`tripsitter rom`, src/tripsitter/host/rom_image.h), held in
// block RAM loaded from a $readmemh file, and played into the device's SPI pins one world at a time as a
// microcontroller sends them: SPI mode 0, most significant bit first, a world only while the ready line is high.
//
// The ROM (layout in rom_image.h, every number big-endian): a 4-byte world count K, then K + 1 4-byte offsets (world
// k is the ROM's bytes offset[k] .. offset[k + 1] - 1), then the worlds, each a whole frame as the link carries it.
// A count of 0 sends nothing.
//
// Worlds. After reset world 0 is chosen. `next` and `prev` (one clock each, from the debounced buttons) choose the
// world after or before the chosen one, wrapping around. A chosen world that differs from the last one sent goes out
// as soon as the device's ready line is high and no world is going out; choices made meanwhile make one world, the
// last chosen (as the host replaces a world not yet sent with a newer one). The frames are sent as the ROM holds
// them, so going back sends an old sequence number again: the device must speak wire v2, which shows every intact
// world (docs/link_format.md, "Sessions and sequence numbers"; docs/rtl.md, "The board").
//
// SPI. SCLK's half period is HALF_CYCLES clocks (5: 10 MHz against 100 MHz, the link's default; ts_spi_rx sees
// every edge from 3 on, and `--device rtl` allows 4 and more). MOSI changes while SCLK is low, HALF_CYCLES clocks
// before the rising edge. Chip select is low from HALF_CYCLES clocks before a world's first bit to HALF_CYCLES after
// its last; between two bytes SCLK stays low 3 clocks longer (the ROM read). After chip select rises the host waits
// for the device's `idle` (its receiver has dealt with every byte: ts_receiver's timing contract) before it looks at
// ready again, as ready falls only when the receiver has checked the frame, clocks after its last bit.
module ts_rom_host #(
    parameter ROM_FILE = "ts_arty_rom.mem",  // $readmemh: two hexadecimal digits a byte, one byte a line
    parameter int ROM_BYTES = 8192,           // block RAM bytes; a power of two
    parameter int HALF_CYCLES = 5,            // SCLK half period in clocks; at least 4
    localparam int AW = $clog2(ROM_BYTES)
) (
    input  logic          clk,
    input  logic          rst,
    input  logic          next,      // one clock: choose the next world
    input  logic          prev,      // one clock: choose the previous world
    input  logic          ready,     // the device's ready line
    input  logic          idle,      // the device's receiver has dealt with every byte it received
    output logic          sclk,
    output logic          mosi,
    output logic          cs_n,
    output logic [AW-1:0] world      // the world chosen
);
  if (ROM_BYTES < 16 || (ROM_BYTES & (ROM_BYTES - 1)) != 0) begin : g_bad_rom
    $error("ts_rom_host: ROM_BYTES must be a power of two, at least 16");
  end
  if (HALF_CYCLES < 4) begin : g_bad_half
    $error("ts_rom_host: HALF_CYCLES must be at least 4 (ts_spi_rx's synchronisers)");
  end
  localparam int TimerW = $clog2(HALF_CYCLES);

  // ---- the ROM: a registered read, data the clock after the address ----------------------------------------------
  logic [7:0]    rom [ROM_BYTES];
  logic [AW-1:0] addr_q;
  logic [7:0]    rom_q;
  initial $readmemh(ROM_FILE, rom);
  always_ff @(posedge clk) rom_q <= rom[addr_q];

  // ---- the worlds' choice ------------------------------------------------------------------------------------------
  logic [AW-1:0] count_q;   // worlds in the ROM
  logic [AW-1:0] chosen_q;  // the world the buttons chose
  logic [AW-1:0] sent_q;    // the world last sent (valid with any_sent_q)
  logic          any_sent_q;
  assign world = chosen_q;

  // ---- the engine --------------------------------------------------------------------------------------------------
  typedef enum logic [3:0] {
    S_COUNT,   // read the world count
    S_IDLE,    // wait for a world to send and the ready line
    S_FIRST,   // read the chosen world's first offset
    S_END,     // and the next one, its end
    S_SELECT,  // chip select low, HALF_CYCLES clocks
    S_LOAD,    // read the byte at ptr_q
    S_LOW,     // SCLK low, MOSI the bit, HALF_CYCLES clocks
    S_HIGH,    // SCLK high, HALF_CYCLES clocks
    S_DESELECT,// after the last bit, HALF_CYCLES clocks, then chip select high
    S_SETTLE   // wait for the receiver to deal with the world
  } state_e;
  state_e state_q;

  logic [2:0]        step_q;    // a 4-byte read's clock (0..5), a byte load's (0..2)
  logic [23:0]       word_q;    // the bytes of a 4-byte number read so far
  logic [AW-1:0]     base_q;    // its address
  logic [AW-1:0]     ptr_q;     // the next byte of the world
  logic [AW-1:0]     end_q;     // the world's end
  logic [AW-1:0]     sending_q; // the world going out
  logic [6:0]        shift_q;   // the byte's bits still to go out, the next one first
  logic [2:0]        bit_q;     // its bits sent
  logic [TimerW-1:0] timer_q;   // clocks left in a half period

  wire half_done = timer_q == '0;
  wire [31:0] word_next = {word_q[23:0], rom_q};
  wire unused_word_high = ^word_next[31:AW];  // offsets and the count are below ROM_BYTES (rom_image.h)
  // A 4-byte read: addresses base .. base + 3 in clocks 0..3, their data in clocks 2..5.
  wire word_done = step_q == 3'd5;

  always_ff @(posedge clk) begin
    if (rst) begin
      state_q <= S_COUNT;
      count_q <= '0;
      chosen_q <= '0;
      sent_q <= '0;
      any_sent_q <= 1'b0;
      step_q <= '0;
      base_q <= '0;
      addr_q <= '0;
      sclk <= 1'b0;
      mosi <= 1'b0;
      cs_n <= 1'b1;
      timer_q <= '0;
    end else begin
      // The buttons, whatever the engine does.
      if (count_q != '0) begin
        if (next) chosen_q <= chosen_q == count_q - 1'b1 ? '0 : chosen_q + 1'b1;
        else if (prev) chosen_q <= chosen_q == '0 ? count_q - 1'b1 : chosen_q - 1'b1;
      end
      if (!half_done) timer_q <= timer_q - 1'b1;

      // 4-byte reads (S_COUNT, S_FIRST, S_END): the address of clock step_q, the data of clock step_q - 2.
      if (state_q == S_COUNT || state_q == S_FIRST || state_q == S_END) begin
        step_q <= word_done ? '0 : step_q + 3'd1;
        if (step_q <= 3'd3) addr_q <= base_q + AW'(step_q);
        if (step_q >= 3'd2) word_q <= word_next[23:0];
      end

      case (state_q)
        S_COUNT:
          if (word_done) begin
            count_q <= AW'(word_next);
            state_q <= S_IDLE;
          end
        S_IDLE:
          if (count_q != '0 && ready && (!any_sent_q || chosen_q != sent_q)) begin
            sending_q <= chosen_q;
            base_q <= AW'(4) + {chosen_q[AW-3:0], 2'b00};
            state_q <= S_FIRST;
          end
        S_FIRST:
          if (word_done) begin
            ptr_q <= AW'(word_next);
            base_q <= base_q + AW'(4);
            state_q <= S_END;
          end
        S_END:
          if (word_done) begin
            end_q <= AW'(word_next);
            if (AW'(word_next) == ptr_q) begin
              // An empty world: nothing to send.
              sent_q <= sending_q;
              any_sent_q <= 1'b1;
              state_q <= S_IDLE;
            end else begin
              cs_n <= 1'b0;
              timer_q <= TimerW'(HALF_CYCLES - 1);
              state_q <= S_SELECT;
            end
          end
        S_SELECT:
          if (half_done) begin
            step_q <= '0;
            state_q <= S_LOAD;
          end
        S_LOAD: begin
          step_q <= step_q + 3'd1;
          if (step_q == 3'd0) addr_q <= ptr_q;
          if (step_q == 3'd2) begin
            shift_q <= rom_q[6:0];
            bit_q <= '0;
            mosi <= rom_q[7];
            timer_q <= TimerW'(HALF_CYCLES - 1);
            state_q <= S_LOW;
          end
        end
        S_LOW:
          if (half_done) begin
            sclk <= 1'b1;
            timer_q <= TimerW'(HALF_CYCLES - 1);
            state_q <= S_HIGH;
          end
        S_HIGH:
          if (half_done) begin
            sclk <= 1'b0;
            timer_q <= TimerW'(HALF_CYCLES - 1);
            if (bit_q != 3'd7) begin
              bit_q <= bit_q + 3'd1;
              shift_q <= {shift_q[5:0], 1'b0};
              mosi <= shift_q[6];
              state_q <= S_LOW;
            end else if (ptr_q + 1'b1 != end_q) begin
              ptr_q <= ptr_q + 1'b1;
              step_q <= '0;
              state_q <= S_LOAD;
            end else begin
              state_q <= S_DESELECT;
            end
          end
        S_DESELECT:
          if (half_done) begin
            cs_n <= 1'b1;
            mosi <= 1'b0;
            step_q <= '0;
            state_q <= S_SETTLE;
          end
        S_SETTLE:
          if (idle) begin
            sent_q <= sending_q;
            any_sent_q <= 1'b1;
            state_q <= S_IDLE;
          end
        default: state_q <= S_IDLE;
      endcase
    end
  end
endmodule
