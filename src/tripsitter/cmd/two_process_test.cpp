// Host and device as two programs talking TCP on loopback, as a user runs them: `tripsitter device
// --listen 127.0.0.1:0 --headless --out-dir D` and `tripsitter host --connect ... --keys F`. What the
// device writes is compared with the same world drawn in one process by board::Board.
//
// No timing assertions: waits poll with generous limits only so that a broken build fails instead of hanging.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include <tripsitter/board/board.h>
#include <tripsitter/core/crc32.h>
#include <tripsitter/link/frame.h>
#include <tripsitter/display/png.h>
#include <tripsitter/host/controls.h>
#include <tripsitter/scene/builtin.h>

#include "command_test_util.h"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
using tripsitter::core::Image444;
using tripsitter::host::Key;

using tripsitter::cmd::test::slurp;

// Polls `ready` every few milliseconds until it holds or `limit` passes.
template <class Ready>
bool eventually(Ready ready, std::chrono::seconds limit = 60s) {
  const auto give_up = Clock::now() + limit;
  while (!ready()) {
    if (Clock::now() > give_up) return false;
    std::this_thread::sleep_for(5ms);
  }
  return true;
}

// The port in the device's "listening on 127.0.0.1:PORT" line, once the whole line is there.
std::string listening_port(const std::string& err) {
  const std::string prefix = "listening on 127.0.0.1:";
  const std::size_t at = err.find(prefix);
  if (at == std::string::npos) return "";
  const std::size_t end = err.find('\n', at);
  if (end == std::string::npos) return "";
  return err.substr(at + prefix.size(), end - at - prefix.size());
}

// One run of the tripsitter binary, standard output and error into files. The destructor kills it if it
// still runs, and always reaps it: no stray processes.
class Process {
 public:
  Process(const std::vector<std::string>& args, const fs::path& out, const fs::path& err) : err_(err) {
    std::vector<std::string> all{TRIPSITTER_BIN};
    all.insert(all.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t files;
    posix_spawn_file_actions_init(&files);
    posix_spawn_file_actions_addopen(&files, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&files, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&files, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int rc = posix_spawn(&pid_, argv[0], &files, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&files);
    if (rc != 0) pid_ = -1;
  }
  Process(const Process&) = delete;
  Process& operator=(const Process&) = delete;
  ~Process() {
    if (pid_ > 0 && !status_) {
      ::kill(pid_, SIGKILL);
      int status = 0;
      ::waitpid(pid_, &status, 0);
    }
  }

  bool started() const { return pid_ > 0; }
  bool running() {
    poll();
    return pid_ > 0 && !status_;
  }
  void signal(int sig) const {
    if (pid_ > 0 && !status_) ::kill(pid_, sig);
  }
  // The exit code, -1 if a signal ended it, or nothing if it still runs after `limit`.
  std::optional<int> wait(std::chrono::seconds limit = 60s) {
    eventually([&] { return !running(); }, limit);
    if (!status_) return std::nullopt;
    return WIFEXITED(*status_) ? WEXITSTATUS(*status_) : -1;
  }
  std::string err() const { return slurp(err_); }
  // The largest resident set it had, in kilobytes, once it has ended.
  long max_rss_kb() const { return max_rss_kb_; }

 private:
  void poll() {
    if (pid_ <= 0 || status_) return;
    int status = 0;
    rusage usage{};
    if (::wait4(pid_, &status, WNOHANG, &usage) == pid_) {
      status_ = status;
      max_rss_kb_ = usage.ru_maxrss;
    }
  }

  pid_t pid_ = -1;
  std::optional<int> status_;
  long max_rss_kb_ = 0;
  fs::path err_;
};

// A peer that speaks to the device byte by byte, as no well-behaved host would: over a plain socket.
class RawPeer {
 public:
  explicit RawPeer(int port) : fd_(::socket(AF_INET, SOCK_STREAM, 0)) {
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<std::uint16_t>(port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    connected_ = fd_ >= 0 && ::connect(fd_, reinterpret_cast<const sockaddr*>(&a), sizeof a) == 0;
  }
  RawPeer(const RawPeer&) = delete;
  RawPeer& operator=(const RawPeer&) = delete;
  ~RawPeer() {
    if (fd_ >= 0) ::close(fd_);
  }
  bool connected() const { return connected_; }
  bool send(const std::vector<std::uint8_t>& bytes) const {
    return ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(bytes.size());
  }
  // The next byte from the device, or -1 when it closed the connection, or -2 when nothing came in `limit`.
  int read_byte(std::chrono::seconds limit = 30s) const {
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(std::chrono::milliseconds(limit).count())) <= 0) return -2;
    std::uint8_t b = 0;
    const ssize_t n = ::recv(fd_, &b, 1, 0);
    return n == 1 ? b : -1;
  }

 private:
  int fd_;
  bool connected_ = false;
};

struct HeldKey {
  Key key;
  int ticks;
};

// The same scene and keys in one process: the board's own host, the keys applied tick by tick with
// apply_held_key as the host program does (1/60 s per tick), then one frame as the monitor shows it.
Image444 expected_frame(const std::vector<HeldKey>& keys, const std::string& scene = "demo") {
  tripsitter::board::Board board(*tripsitter::scene::builtin(scene), {});
  for (const HeldKey& k : keys)
    for (int i = 0; i < k.ticks; ++i) tripsitter::host::apply_held_key(board.host().camera(), k.key, 1.0 / 60);
  return board.show().image;
}

class TwoProcesses : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = tripsitter::cmd::test::scratch_dir("tripsitter_2p_");
    fs::create_directories(dir_ / "frames");
  }
  void TearDown() override {
    device_.reset();  // kills and reaps it if a failed assertion left it running
    fs::remove_all(dir_);
  }

  fs::path path(const std::string& name) const { return dir_ / name; }
  fs::path frames() const { return dir_ / "frames"; }

  void write(const std::string& name, const std::string& text) const { std::ofstream(path(name)) << text; }

  // Starts the headless device on a port of the system's choice (or on `port`, to restart it where it was)
  // and reads the port from its stderr.
  void start_device(const std::vector<std::string>& extra = {}, const std::string& port_wanted = "0") {
    std::vector<std::string> args{"device", "--listen", "127.0.0.1:" + port_wanted, "--headless", "--out-dir",
                                  frames().string()};
    args.insert(args.end(), extra.begin(), extra.end());
    device_.reset();
    device_.emplace(args, path("device.out"), path("device.err"));
    ASSERT_TRUE(device_->started());
    ASSERT_TRUE(eventually([&] { return !listening_port(device_->err()).empty() || !device_->running(); }, 30s));
    const std::string port = listening_port(device_->err());
    ASSERT_FALSE(port.empty()) << device_->err();
    address_ = "127.0.0.1:" + port;
  }

  // Stops the device with SIGTERM; it must exit cleanly.
  void stop_device() {
    device_->signal(SIGTERM);
    const std::optional<int> code = device_->wait();
    ASSERT_TRUE(code.has_value()) << "the device did not stop on SIGTERM";
    EXPECT_EQ(*code, 0) << device_->err();
  }

  std::unique_ptr<Process> start_host(const std::string& name, std::vector<std::string> extra) {
    std::vector<std::string> args{"host", "--connect", address_};
    args.insert(args.end(), extra.begin(), extra.end());
    return std::make_unique<Process>(args, path(name + ".out"), path(name + ".err"));
  }

  // Runs a host to the end; returns its exit code (the test fails if it hangs).
  int run_host(const std::string& name, std::vector<std::string> extra, std::string* err = nullptr) {
    auto host = start_host(name, std::move(extra));
    const std::optional<int> code = host->wait();
    if (err) *err = host->err();
    EXPECT_TRUE(code.has_value()) << "host " << name << " did not finish";
    return code.value_or(-2);
  }

  // The frame files the device has written, by frame number.
  std::vector<std::pair<long, fs::path>> frame_files() const {
    std::vector<std::pair<long, fs::path>> out;
    for (const auto& e : fs::directory_iterator(frames())) {
      // frame_NNNNNN.png, at least six digits (not the writer's temporary files)
      const std::string n = e.path().filename().string();
      if (n.size() < 16 || !n.starts_with("frame_") || !n.ends_with(".png")) continue;
      const std::string digits = n.substr(6, n.size() - 10);
      if (std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
        out.emplace_back(std::stol(digits), e.path());
    }
    std::sort(out.begin(), out.end());
    return out;
  }

  std::optional<Image444> newest_frame() const {
    const auto files = frame_files();
    if (files.empty()) return std::nullopt;
    auto img = tripsitter::display::read_png(files.back().second.string());
    if (!img.ok()) return std::nullopt;
    return img.value();
  }

  static std::string describe_difference(const std::optional<Image444>& got, const Image444& want) {
    if (!got) return "no frame written";
    const auto d = tripsitter::core::diff(*got, want);
    return std::to_string(d.differing) + " of " + std::to_string(d.pixels) + " pixels differ";
  }

  fs::path dir_;
  std::optional<Process> device_;
  std::string address_;
};

TEST_F(TwoProcesses, TheDeviceShowsTheInitialWorldAndThenTheScriptsFinalWorld) {
  start_device();

  // No script: the scene as loaded.
  std::string err;
  ASSERT_EQ(run_host("initial", {"--scene", "demo"}, &err), 0) << err;
  EXPECT_NE(err.find("the device took the last world"), std::string::npos) << err;
  const Image444 initial = expected_frame({});
  // The device answers the last world only after its frame went to the sink: the file is there already.
  std::optional<Image444> got = newest_frame();
  ASSERT_TRUE(got.has_value());
  EXPECT_TRUE(*got == initial) << describe_difference(got, initial);

  // A script, played in real time.
  write("keys.txt", "# forward, look left, step right\nW 500ms\nJ 200ms\nD 100ms\n");
  ASSERT_EQ(run_host("scripted", {"--keys", path("keys.txt").string()}, &err), 0) << err;
  EXPECT_NE(err.find("48 ticks"), std::string::npos) << err;
  const Image444 final_frame = expected_frame({{Key::kW, 30}, {Key::kJ, 12}, {Key::kD, 6}});
  ASSERT_FALSE(final_frame == initial);  // the script does change the view
  got = newest_frame();
  EXPECT_TRUE(got && *got == final_frame) << describe_difference(got, final_frame);

  // The same script played at once, v2 transfers of 7 bytes: the same last world.
  const std::size_t before = frame_files().size();
  ASSERT_EQ(run_host("fast", {"--keys", path("keys.txt").string(), "--fast", "--transfer-bytes", "7"}, &err), 0)
      << err;
  EXPECT_GT(frame_files().size(), before);
  got = newest_frame();
  EXPECT_TRUE(got && *got == final_frame) << describe_difference(got, final_frame);

  ASSERT_TRUE(device_->running());
  stop_device();
  const std::string device_err = device_->err();
  EXPECT_NE(device_err.find("hosts: 3 served, 0 refused"), std::string::npos) << device_err;
  EXPECT_NE(device_err.find("0 rejected"), std::string::npos) << device_err;
}

TEST_F(TwoProcesses, AKilledHostLeavesItsLastWorldAndTheNextHostIsServed) {
  start_device();

  // Host A walks forward for 300 ms, then waits (sending the same view every tick) until it is killed.
  write("a.txt", "W 300ms\nwait 60s\n");
  auto a = start_host("a", {"--keys", path("a.txt").string()});
  const Image444 a_view = expected_frame({{Key::kW, 18}});
  ASSERT_TRUE(eventually([&] {
    const auto got = newest_frame();
    return (got && *got == a_view) || !a->running();
  })) << describe_difference(newest_frame(), a_view);
  ASSERT_TRUE(a->running()) << a->err();

  // While A is served, another host is refused.
  std::string err;
  EXPECT_EQ(run_host("c", {"--fast"}, &err), 1);
  EXPECT_NE(err.find("busy with another host"), std::string::npos) << err;

  // A dies without a word, possibly in the middle of a world.
  a->signal(SIGKILL);
  ASSERT_EQ(a->wait(), -1);
  ASSERT_TRUE(eventually([&] { return device_->err().find("went away") != std::string::npos; })) << device_->err();
  ASSERT_TRUE(device_->running()) << device_->err();
  std::optional<Image444> got = newest_frame();
  EXPECT_TRUE(got && *got == a_view) << describe_difference(got, a_view);  // the last good world stays

  // Host B, a new program from the scene as loaded, is served and its last world shown.
  write("b.txt", "L 300ms\nS 200ms\nQ 100ms\nI\n");
  ASSERT_EQ(run_host("b", {"--keys", path("b.txt").string(), "--fast"}, &err), 0) << err;
  const Image444 b_view = expected_frame({{Key::kL, 18}, {Key::kS, 12}, {Key::kQ, 6}, {Key::kI, 1}});
  got = newest_frame();
  EXPECT_TRUE(got && *got == b_view) << describe_difference(got, b_view);

  ASSERT_TRUE(device_->running());
  stop_device();
  EXPECT_NE(device_->err().find("hosts: 2 served, 1 refused"), std::string::npos) << device_->err();
}

TEST_F(TwoProcesses, TheV1WireWorksOverTheStreamToo) {
  start_device({"--wire", "v1", "--preset", "board-2023"});
  write("keys.txt", "S 250ms\nE 100ms\n");
  std::string err;
  ASSERT_EQ(run_host("v1", {"--keys", path("keys.txt").string(), "--wire", "v1", "--preset", "board-2023", "--fast"},
                     &err),
            0)
      << err;
  tripsitter::board::BoardConfig config;
  config.preset = *tripsitter::device::preset_by_name("board-2023");
  config.wire = tripsitter::link::WireVersion::kV1;
  tripsitter::board::Board board(*tripsitter::scene::builtin("demo"), config);
  for (int i = 0; i < 15; ++i) tripsitter::host::apply_held_key(board.host().camera(), Key::kS, 1.0 / 60);
  for (int i = 0; i < 6; ++i) tripsitter::host::apply_held_key(board.host().camera(), Key::kE, 1.0 / 60);
  const Image444 want = board.show().image;
  const std::optional<Image444> got = newest_frame();
  EXPECT_TRUE(got && *got == want) << describe_difference(got, want);
  stop_device();
}

TEST_F(TwoProcesses, AMismatchedHostIsToldItsWorldWasRejected) {
  start_device({"--preset", "board-2023"});  // 3 fractional bits; the host's wide preset sends 4
  std::string err;
  EXPECT_EQ(run_host("wide", {"--fast"}, &err), 1);
  EXPECT_NE(err.find("rejected the last world"), std::string::npos) << err;
  ASSERT_TRUE(device_->running());
  stop_device();
  EXPECT_NE(device_->err().find("format mismatch"), std::string::npos) << device_->err();
  EXPECT_TRUE(frame_files().empty());
}

// The path preset as a program: it path-traces the host's v2 worlds with the --spp and --depth given, and keeps
// accumulating while the worlds the host sends keep the same content. What it writes is compared with a board of the
// same preset drawing the same worlds in one process: the first frame of a world, or the k-th of a still one.
TEST_F(TwoProcesses, ThePathPresetTracesTheHostsWorldsAndAccumulatesWhileTheyStayTheSame) {
  start_device({"--preset", "path", "--spp", "2", "--depth", "3"});
  EXPECT_NE(device_->err().find("preset path (2 samples per pixel per frame, 3 rays per path"), std::string::npos)
      << device_->err();
  tripsitter::board::BoardConfig config;
  config.preset = tripsitter::device::path_preset();
  config.preset.path->spp = 2;
  config.preset.path->depth = 3;
  const auto board = [&config](const std::vector<HeldKey>& keys) {
    auto b = std::make_unique<tripsitter::board::Board>(*tripsitter::scene::builtin("cluster"), config);
    for (const HeldKey& k : keys)
      for (int i = 0; i < k.ticks; ++i) tripsitter::host::apply_held_key(b->host().camera(), k.key, 1.0 / 60);
    return b;
  };

  // The three hosts run first, and the device stops, before the board draws anything: the device draws as fast as
  // it can (slower than real time in the sanitizer builds) while it runs, so that every frame the board drew
  // meanwhile would share the machine with it, and every one drawn between the first two hosts would be a frame
  // more for the search below.
  // The scene as loaded: the first frame of its world, two samples per pixel.
  std::string err;
  ASSERT_EQ(run_host("initial", {"--scene", "cluster", "--preset", "path"}, &err), 0) << err;
  const std::optional<Image444> got_first = newest_frame();
  const std::size_t files = frame_files().size();

  // Another host sends the same world again: a new world of the same content, so frame memory went on
  // accumulating; how many frames the device drew meanwhile is up to the clock, so the frame written is the board's
  // k-th for some k >= 2 (from k = 127 on, every pixel has its 254 samples and the picture stays).
  ASSERT_EQ(run_host("again", {"--scene", "cluster"}, &err), 0) << err;
  ASSERT_GT(frame_files().size(), files);
  const std::optional<Image444> got_again = newest_frame();

  // A moved camera: a world of new content, traced from its first sample.
  write("keys.txt", "E 100ms\n");
  ASSERT_EQ(run_host("orbit", {"--scene", "cluster", "--keys", path("keys.txt").string(), "--fast"}, &err), 0) << err;
  const std::optional<Image444> got_moved = newest_frame();

  stop_device();
  EXPECT_NE(device_->err().find("0 rejected"), std::string::npos) << device_->err();

  // The board's first frame of the world is the initial host's, and the first of the frames searched.
  auto still = board({});
  const Image444 first = still->show().image;
  EXPECT_TRUE(got_first && *got_first == first) << describe_difference(got_first, first);
  ASSERT_TRUE(got_again.has_value());
  EXPECT_FALSE(*got_again == first);
  int k = 1;
  bool found = false;
  while (!found && k < 128) {
    ++k;
    found = still->show().image == *got_again;
  }
  EXPECT_TRUE(found) << "the frame is none of the board's first 128 frames of the world";

  const Image444 moved = board({{Key::kE, 6}})->show().image;
  EXPECT_TRUE(got_moved && *got_moved == moved) << describe_difference(got_moved, moved);
}

TEST_F(TwoProcesses, TheDeviceStopsAfterFramesAndWritesNothingWithoutAWorld) {
  start_device({"--frames", "5"});
  const std::optional<int> code = device_->wait();
  ASSERT_TRUE(code.has_value());
  EXPECT_EQ(*code, 0) << device_->err();
  EXPECT_NE(device_->err().find("5 frames drawn"), std::string::npos) << device_->err();
  EXPECT_TRUE(frame_files().empty());
}

TEST_F(TwoProcesses, UsageErrorsExitTwoAndSayWhatAndWhere) {
  // Nothing listens on a port that was just free.
  start_device({"--frames", "1"});
  ASSERT_TRUE(device_->wait().has_value());
  std::string err;
  EXPECT_EQ(run_host("refused", {}, &err), 2);
  EXPECT_NE(err.find("cannot connect to " + address_), std::string::npos) << err;
  EXPECT_NE(err.find("tripsitter device --listen " + address_), std::string::npos) << err;

  write("bad.txt", "W 500ms\n  X 1s\n");
  EXPECT_EQ(run_host("badkeys", {"--keys", path("bad.txt").string()}, &err), 2);
  EXPECT_NE(err.find(path("bad.txt").string() + ":2:3: unknown key 'X'"), std::string::npos) << err;

  auto run = [&](const std::vector<std::string>& args) {
    Process p(args, path("usage.out"), path("usage.err"));
    const std::optional<int> code = p.wait();
    err = p.err();
    return code.value_or(-2);
  };
  EXPECT_EQ(run({"host", "--connect", "127.0.0.1"}), 2);
  EXPECT_NE(err.find("address '127.0.0.1': missing ':PORT'"), std::string::npos) << err;
  EXPECT_EQ(run({"device", "--listen", "127.0.0.1:0", "--out-dir", frames().string()}), 2);
  EXPECT_NE(err.find("--out-dir goes with --headless"), std::string::npos) << err;
  EXPECT_EQ(run({"device", "--listen", "127.0.0.1:99999", "--headless", "--out-dir", frames().string()}), 2);
  EXPECT_NE(err.find("port 99999 is above 65535"), std::string::npos) << err;
  EXPECT_EQ(run({"device", "--listen", "127.0.0.1:0", "--headless"}), 2);
  EXPECT_NE(err.find("--out-dir"), std::string::npos) << err;
}

// ---- The link under faults (docs/link_format.md, "Disconnects and other hosts") ----

// The device is killed and started again on the same port while a host plays a script: the host reconnects
// under a new session, and the restarted device shows the script's last world.
TEST_F(TwoProcesses, AHostReconnectsToARestartedDevice) {
  start_device();
  const std::string port = address_.substr(address_.rfind(':') + 1);
  write("keys.txt", "W 500ms\nwait 2s\nJ 200ms\n");
  auto host = start_host("host", {"--keys", path("keys.txt").string()});
  ASSERT_TRUE(eventually([&] { return !frame_files().empty() || !host->running(); }));
  device_->signal(SIGKILL);
  ASSERT_EQ(device_->wait(), -1);
  start_device({}, port);
  const std::optional<int> code = host->wait();
  ASSERT_TRUE(code.has_value());
  const std::string err = host->err();
  EXPECT_EQ(*code, 0) << err;
  // A killed device's socket closes or resets, as the kernel decides: either way the host reconnects.
  EXPECT_NE(err.find("; reconnecting\n"), std::string::npos) << err;
  EXPECT_NE(err.find("reconnected to " + address_), std::string::npos) << err;
  const Image444 want = expected_frame({{Key::kW, 30}, {Key::kJ, 12}});
  const std::optional<Image444> got = newest_frame();
  EXPECT_TRUE(got && *got == want) << describe_difference(got, want);
  stop_device();
  EXPECT_NE(device_->err().find("0 replayed, 0 rejected"), std::string::npos) << device_->err();
}

// Hostile and broken peers, one after the other, against one device: a host that sends a byte now and then,
// a header announcing 4 GB with a CRC that matches, half a frame and gone. The device drops or refuses each,
// never holds more memory than a world, and serves the next real host.
TEST_F(TwoProcesses, HostilePeersCostTheDeviceNothing) {
  start_device({"--host-timeout", "1"});
  const int port = std::stoi(address_.substr(address_.rfind(':') + 1));
  std::string err;
  ASSERT_EQ(run_host("first", {"--fast"}, &err), 0) << err;
  const Image444 first = expected_frame({});

  {  // One byte a second (the wait for the device's answer paces it): dropped after a second without a world.
    RawPeer slow(port);
    ASSERT_TRUE(slow.connected());
    ASSERT_EQ(slow.read_byte(), 'R');
    int answer = -2;
    for (int i = 0; i < 30 && answer == -2; ++i) {
      slow.send({0x54});
      answer = slow.read_byte(1s);
    }
    EXPECT_EQ(answer, -1) << "the device closes the connection";
  }
  ASSERT_TRUE(eventually([&] { return device_->err().find("without completing a world") != std::string::npos; }))
      << device_->err();

  {  // A header announcing 178,956,970 spheres (4 GB), honest CRC: refused at once, answered 'X'.
    RawPeer greedy(port);
    ASSERT_TRUE(greedy.connected());
    ASSERT_EQ(greedy.read_byte(), 'R');
    tripsitter::link::World w;
    w.session = 5;
    w.sequence = 1;
    std::vector<std::uint8_t> header = tripsitter::link::encode_frame(tripsitter::link::WireVersion::kV3, w);
    header.resize(tripsitter::link::kV3HeaderBytes - 4);
    const std::uint32_t count = 178'956'970;
    const std::uint32_t length = count * 24;
    for (std::size_t k = 0; k < 4; ++k) {
      header[16 + k] = static_cast<std::uint8_t>(count >> (24 - 8 * k));
      header[20 + k] = static_cast<std::uint8_t>(length >> (24 - 8 * k));
    }
    const std::uint32_t crc = tripsitter::core::crc32(header);
    for (int k = 0; k < 4; ++k) header.push_back(static_cast<std::uint8_t>(crc >> (24 - 8 * k)));
    ASSERT_TRUE(greedy.send(header));
    EXPECT_EQ(greedy.read_byte(), 'X');
  }

  {  // Half a frame, then gone.
    RawPeer quitter(port);
    ASSERT_TRUE(quitter.connected());
    ASSERT_EQ(quitter.read_byte(), 'R');
    tripsitter::link::World w;
    w.session = 6;
    w.sequence = 1;
    w.frac_bits = 4;
    w.spheres.resize(40, {0, 0, 6400, 1024, 0, {200, 0, 0}, 0, 6144});
    const std::vector<std::uint8_t> frame = tripsitter::link::encode_frame(tripsitter::link::WireVersion::kV3, w);
    ASSERT_TRUE(quitter.send(std::vector<std::uint8_t>(frame.begin(), frame.begin() + frame.size() / 2)));
  }
  ASSERT_TRUE(eventually([&] { return device_->err().find("truncated") != std::string::npos; })) << device_->err();
  std::optional<Image444> got = newest_frame();
  EXPECT_TRUE(got && *got == first) << describe_difference(got, first);  // the last good world stays

  write("keys.txt", "E 100ms\n");
  ASSERT_EQ(run_host("last", {"--keys", path("keys.txt").string(), "--fast"}, &err), 0) << err;
  const Image444 last = expected_frame({{Key::kE, 6}});
  got = newest_frame();
  EXPECT_TRUE(got && *got == last) << describe_difference(got, last);

  stop_device();
  const std::string d = device_->err();
  EXPECT_NE(d.find("too many spheres"), std::string::npos) << d;
  EXPECT_NE(d.find("hosts: 5 served, 0 refused"), std::string::npos) << d;
  // Its memory stays that of a device with one world: far below the 4 GB it was offered.
  EXPECT_LT(device_->max_rss_kb(), 400 * 1024);
}

// Fifty hosts start at once: the first to connect is served and holds the device for its script; every other
// one is told the device is busy and exits 1 saying so.
TEST_F(TwoProcesses, OfFiftyHostsAtOnceOneIsServedAndTheOthersAreToldTheDeviceIsBusy) {
  start_device();
  write("keys.txt", "wait 60s\n");
  std::vector<std::unique_ptr<Process>> hosts;
  for (int i = 0; i < 50; ++i) {
    std::string name = std::to_string(i);
    name.insert(0, "host_");
    hosts.push_back(start_host(name, {"--keys", path("keys.txt").string()}));
  }
  std::size_t busy = 0;
  Process* served = nullptr;
  ASSERT_TRUE(eventually([&] {
    busy = 0;
    served = nullptr;
    for (auto& h : hosts) {
      if (h->running()) {
        served = h.get();
      } else {
        ++busy;
      }
    }
    return busy == 49;
  })) << busy << " of 50 hosts have exited";
  for (auto& h : hosts) {
    if (h.get() == served) continue;
    EXPECT_EQ(h->wait(), 1);
    EXPECT_NE(h->err().find("is busy with another host"), std::string::npos) << h->err();
  }
  ASSERT_NE(served, nullptr);
  EXPECT_NE(served->err().find("host: connected to"), std::string::npos) << served->err();
  served->signal(SIGKILL);
  served->wait();
  stop_device();
  EXPECT_NE(device_->err().find("hosts: 1 served, 49 refused"), std::string::npos) << device_->err();
}

}  // namespace
