// The path preset's scatter unit (src/tripsitter/device/path_kernel.h, scatter()): the bounce of a path at its hit,
// whatever the material, behind one port that takes a bounce a cycle. A lambertian or metal bounce goes through
// ts_path_diffuse, a dielectric through ts_path_dielectric; the diffuse results wait 3 cycles more, so that every
// result comes out Latency = 23 cycles after its bounce, in order, with its tag.
//
// Out: `bounce` as the model's Bounce (0 scattered along `next`, 1 straight on, 2 absorbed), `into` (the ray is
// inside the sphere after the bounce: a dielectric's refraction or a reflection inside), `refracted`, and `drew`:
// the sample's draw was taken, so its stream moves on.
module ts_path_scatter #(
    parameter int TAG_W = 1
) (
    input  logic             clk,
    input  logic             rst,
    input  logic             in_valid,
    input  logic [1:0]       in_material,   // the wire's codes: 0 lambertian, 1 metal, 2 dielectric
    input  logic [3*17-1:0]  in_dir,        // x, y, z from the low bits: 17 bits signed each, times 2^14
    input  logic [3*17-1:0]  in_normal,     // outward, as in_dir
    input  logic             in_inside,     // the ray is inside the sphere it hit (a dielectric's far side)
    input  logic [15:0]      in_fuzz,       // metal: times 2^-16
    input  logic [17:0]      in_eta_enter,  // dielectric: times 2^14
    input  logic [17:0]      in_eta_leave,
    input  logic [14:0]      in_r0,
    input  logic             in_straight,   // dielectric of index exactly 1
    input  logic [31:0]      in_draw,
    input  logic [TAG_W-1:0] in_tag,
    output logic             out_valid,
    output logic [1:0]       out_bounce,
    output logic             out_into,
    output logic             out_refracted,
    output logic             out_drew,
    output logic [3*24-1:0]  out_next,
    output logic [TAG_W-1:0] out_tag
);
  localparam int DiffuseLatency = 20;
  localparam int Latency = 23;
  localparam logic [1:0] Scattered = 2'd0, Straight = 2'd1, Absorbed = 2'd2;

  logic dielectric;
  assign dielectric = in_material == 2'd2;

  logic               d_valid, d_straight, d_into, d_refracted, d_drew;
  logic [3*24-1:0]    d_next;
  logic [TAG_W-1:0]   d_tag;
  ts_path_dielectric #(
      .TAG_W(TAG_W)
  ) u_dielectric (
      .clk,
      .rst,
      .in_valid    (in_valid && dielectric),
      .in_dir,
      .in_normal,
      .in_inside,
      .in_eta_enter,
      .in_eta_leave,
      .in_r0,
      .in_straight,
      .in_draw,
      .in_tag,
      .out_valid   (d_valid),
      .out_straight(d_straight),
      .out_into    (d_into),
      .out_refracted(d_refracted),
      .out_drew    (d_drew),
      .out_next    (d_next),
      .out_tag     (d_tag)
  );

  logic               m_valid, m_absorbed, m_drew;
  logic [3*24-1:0]    m_next;
  logic [TAG_W-1:0]   m_tag;
  ts_path_diffuse #(
      .TAG_W(TAG_W)
  ) u_diffuse (
      .clk,
      .rst,
      .in_valid    (in_valid && !dielectric),
      .in_metal    (in_material == 2'd1),
      .in_dir,
      .in_normal,
      .in_fuzz,
      .in_draw,
      .in_tag,
      .out_valid   (m_valid),
      .out_absorbed(m_absorbed),
      .out_drew    (m_drew),
      .out_next    (m_next),
      .out_tag     (m_tag)
  );

  // The diffuse results, Latency - DiffuseLatency cycles later: then at most one of the two is valid a cycle, as at
  // most one bounce went in.
  localparam int WaitW = 2 + 3 * 24 + TAG_W;
  logic [2:0]       m_valid_q;
  logic [WaitW-1:0] m_late;
  always_ff @(posedge clk) begin
    if (rst) m_valid_q <= '0;
    else m_valid_q <= {m_valid_q[1:0], m_valid};
  end
  ts_artix_delay #(
      .W(WaitW),
      .N(Latency - DiffuseLatency)
  ) u_wait (
      .clk,
      .in ({m_absorbed, m_drew, m_next, m_tag}),
      .out(m_late)
  );

  logic late_absorbed, late_drew;
  logic [3*24-1:0] late_next;
  logic [TAG_W-1:0] late_tag;
  assign {late_absorbed, late_drew, late_next, late_tag} = m_late;
  assign out_valid = d_valid || m_valid_q[2];
  assign out_bounce = d_valid ? (d_straight ? Straight : Scattered) : (late_absorbed ? Absorbed : Scattered);
  assign out_into = d_valid && d_into;
  assign out_refracted = d_valid && d_refracted;
  assign out_drew = d_valid ? d_drew : late_drew;
  assign out_next = d_valid ? d_next : late_next;
  assign out_tag = d_valid ? d_tag : late_tag;
endmodule
