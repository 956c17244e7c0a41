// Output follows the IEEE 1364-2005 section 18.2 grammar: declaration commands each closed by $end, then
// "#<time>" lines each followed by the value changes at that time; scalars as "<0|1><id>", vectors as
// "b<bits> <id>". The first sample's values are written inside $dumpvars ... $end at time 0.
#include <tripsitter/display/vcd.h>

#include <cstdio>

namespace tripsitter::display {
namespace {

// Identifier codes. '$' is skipped so that no identifier can be mistaken for a keyword.
constexpr char kHsyncId = '!';
constexpr char kVsyncId = '"';
constexpr char kRedId = '#';
constexpr char kGreenId = '%';
constexpr char kBlueId = '&';

void write_scalar(std::ostream& out, bool v, char id) { out << (v ? '1' : '0') << id << '\n'; }

void write_nibble(std::ostream& out, int v, char id) {
  char bits[] = "b0000 ";
  for (int i = 0; i < 4; ++i) bits[1 + i] = ((v >> (3 - i)) & 1) ? '1' : '0';
  out << bits << id << '\n';
}

}  // namespace

VcdWriter::VcdWriter(std::ostream& out, std::uint64_t pixel_period_ns) : out_(out), period_ns_(pixel_period_ns) {
  out_ << "$version TripSitter VGA model $end\n"
       << "$comment one sample per pixel clock of " << period_ns_ << " ns $end\n"
       << "$timescale 1ns $end\n"
       << "$scope module vga $end\n"
       << "$var wire 1 " << kHsyncId << " hsync_n $end\n"
       << "$var wire 1 " << kVsyncId << " vsync_n $end\n"
       << "$var wire 4 " << kRedId << " r $end\n"
       << "$var wire 4 " << kGreenId << " g $end\n"
       << "$var wire 4 " << kBlueId << " b $end\n"
       << "$upscope $end\n"
       << "$enddefinitions $end\n";
}

void VcdWriter::sample(const device::VgaSample& s) {
  const std::uint64_t time_ns = samples_ * period_ns_;
  if (first_) {
    out_ << '#' << time_ns << "\n$dumpvars\n";
    write_scalar(out_, s.hsync_n, kHsyncId);
    write_scalar(out_, s.vsync_n, kVsyncId);
    write_nibble(out_, s.colour.r(), kRedId);
    write_nibble(out_, s.colour.g(), kGreenId);
    write_nibble(out_, s.colour.b(), kBlueId);
    out_ << "$end\n";
    first_ = false;
  } else if (s != last_) {
    out_ << '#' << time_ns << '\n';
    if (s.hsync_n != last_.hsync_n) write_scalar(out_, s.hsync_n, kHsyncId);
    if (s.vsync_n != last_.vsync_n) write_scalar(out_, s.vsync_n, kVsyncId);
    if (s.colour.r() != last_.colour.r()) write_nibble(out_, s.colour.r(), kRedId);
    if (s.colour.g() != last_.colour.g()) write_nibble(out_, s.colour.g(), kGreenId);
    if (s.colour.b() != last_.colour.b()) write_nibble(out_, s.colour.b(), kBlueId);
  }
  last_ = s;
  ++samples_;
}

void VcdWriter::finish() { out_ << '#' << samples_ * period_ns_ << '\n'; }

core::Result<std::unique_ptr<VcdFile>, IoError> VcdFile::open(const std::string& path, std::uint64_t max_samples) {
  std::unique_ptr<VcdFile> file(new VcdFile(path, max_samples));
  if (!file->file_) {
    file->kept_ = true;  // nothing of ours is there to remove
    return IoError{path + ": cannot open for writing"};
  }
  return file;
}

// The writer's header goes to the stream as it is constructed; a stream that failed to open takes nothing.
VcdFile::VcdFile(std::string path, std::uint64_t max_samples)
    : path_(std::move(path)), max_samples_(max_samples), file_(path_, std::ios::binary | std::ios::trunc), writer_(file_) {}

VcdFile::~VcdFile() {
  if (kept_) return;
  file_.close();
  std::remove(path_.c_str());
}

core::Result<std::uint64_t, IoError> VcdFile::keep() {
  writer_.finish();
  file_.close();
  if (!file_) return IoError{path_ + ": write failed"};
  kept_ = true;
  return writer_.samples();
}

}  // namespace tripsitter::display
