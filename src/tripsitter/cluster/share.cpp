#include <tripsitter/cluster/share.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <exception>
#include <memory>
#include <thread>
#include <type_traits>
#include <vector>

namespace tripsitter::cluster {
namespace {

// Message tags. Messages from one rank with one tag arrive in the order they were sent.
constexpr int kProgressTag = 1;  // a rank's samples traced so far, one std::uint64_t; the last one is its total
constexpr int kRowsTag = 2;      // all rows of a still that a rank traced, in place (rows_type)
constexpr int kFrameTag = 3;     // one frame of an animation, 8-bit RGB
constexpr int kAlbedoTag = 4;    // the rows of a still's feature buffers (render/aov.h), as kRowsTag's
constexpr int kNormalTag = 5;
constexpr int kDepthTag = 6;

// A rank that waits polls with short sleeps rather than blocking in MPI: Open MPI's blocking calls spin,
// and on a machine with as many ranks as cores that core would be taken from the ranks still tracing.
constexpr auto kPoll = std::chrono::milliseconds(5);
constexpr auto kProgressPeriod = std::chrono::milliseconds(100);

void wait(MPI_Request& request) {
  for (int done = 0;;) {
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    if (done != 0) return;
    std::this_thread::sleep_for(kPoll);
  }
}

// Rows a rank traces: rank, rank + size, ... below height.
int rows_of(int rank, int size, int height) { return rank < height ? (height - rank + size - 1) / size : 0; }

static_assert(std::is_trivially_copyable_v<render::Vec3f> && sizeof(render::Vec3f) == 3 * sizeof(float),
              "rows go over MPI as plain floats");

// The rows of one rank in one plane of `floats` floats per pixel, as one MPI datatype starting at its first row's
// first pixel: blocks of floats * width floats, `size` rows apart. Freed with the object.
class RowsType {
 public:
  RowsType(int rank, int size, int width, int height, int floats) : rows_(rows_of(rank, size, height)) {
    const MPI_Aint row_bytes = static_cast<MPI_Aint>(width) * floats * static_cast<MPI_Aint>(sizeof(float));
    MPI_Type_create_hvector(rows_, floats * width, row_bytes * size, MPI_FLOAT, &type_);
    MPI_Type_commit(&type_);
  }
  ~RowsType() { MPI_Type_free(&type_); }
  RowsType(const RowsType&) = delete;
  RowsType& operator=(const RowsType&) = delete;
  int rows() const { return rows_; }
  MPI_Datatype type() const { return type_; }

 private:
  int rows_;
  MPI_Datatype type_ = MPI_DATATYPE_NULL;
};

// A plane of the picture that goes to rank 0 row by row: the image, or one of the feature buffers.
struct Plane {
  float* data;
  int floats;  // per pixel
  int tag;
  float* row(int r, int width) const { return data + static_cast<std::size_t>(r) * static_cast<std::size_t>(width) * floats; }
};

std::vector<Plane> planes_of(core::ImageRgbF& image, render::Aovs* aovs) {
  std::vector<Plane> planes{{&image.pixels.data()->x, 3, kRowsTag}};
  if (aovs != nullptr) {
    planes.push_back({&aovs->albedo.data()->x, 3, kAlbedoTag});
    planes.push_back({&aovs->normal.data()->x, 3, kNormalTag});
    planes.push_back({aovs->depth.data(), 1, kDepthTag});
  }
  return planes;
}

}  // namespace

core::ImageRgbF render_path_shared(const Job& job, const render::PathScene& scene, const render::ThinLensCamera& camera,
                                     const render::PathSettings& settings,
                                     const std::function<void(std::uint64_t)>& on_samples, render::Aovs* aovs) {
  const int rank = job.rank(), size = job.size();
  const int width = settings.width, height = settings.height;
  core::ImageRgbF image{width, height, std::vector<render::Vec3f>(render::Aovs::pixels(width, height))};
  if (aovs != nullptr) *aovs = render::Aovs(width, height);
  const std::vector<Plane> planes = planes_of(image, aovs);
  const auto samples_of = [&](int r) {
    return static_cast<std::uint64_t>(rows_of(r, size, settings.height)) * settings.row_samples();
  };

  // Rank 0 posts its receives before tracing, so the other ranks' rows land in the image whenever they come.
  // rows_received[r] holds rank r's requests, one per plane.
  std::vector<std::unique_ptr<RowsType>> types;
  std::vector<std::vector<MPI_Request>> rows_received(static_cast<std::size_t>(size),
                                                      std::vector<MPI_Request>(planes.size(), MPI_REQUEST_NULL));
  if (job.is_root()) {
    for (int r = 1; r < size; ++r) {
      for (std::size_t p = 0; p < planes.size(); ++p) {
        types.push_back(std::make_unique<RowsType>(r, size, width, height, planes[p].floats));
        if (types.back()->rows() > 0)
          MPI_Irecv(planes[p].row(r, width), 1, types.back()->type(), r, planes[p].tag, MPI_COMM_WORLD,
                    &rows_received[static_cast<std::size_t>(r)][p]);
      }
    }
  }

  // This rank's rows are traced on another thread while this one, the only one calling MPI, reports progress.
  std::atomic<std::uint64_t> traced{0};
  std::atomic<bool> finished{false};
  std::exception_ptr error;
  std::jthread tracer([&] {
    try {
      render::render_path_rows(
          scene, camera, settings, rank, size, image,
          [&](int) {
            traced.fetch_add(settings.row_samples(), std::memory_order_relaxed);
            job.test_kill_point();
          },
          aovs);
    } catch (...) {
      error = std::current_exception();
    }
    finished.store(true, std::memory_order_release);
  });

  if (job.is_root()) {
    // Samples counted per rank. Another rank is done when its rows have arrived and so has its last count,
    // which is its total: then no message of it is left unreceived.
    std::vector<std::uint64_t> counted(static_cast<std::size_t>(size), 0);
    std::vector<bool> counted_all(static_cast<std::size_t>(size), false);
    std::uint64_t reported = 0;
    for (bool done = false; !done;) {
      const bool traced_all = finished.load(std::memory_order_acquire);
      counted[0] = traced.load(std::memory_order_relaxed);
      for (int waiting = 1; waiting != 0;) {
        MPI_Status status;
        MPI_Iprobe(MPI_ANY_SOURCE, kProgressTag, MPI_COMM_WORLD, &waiting, &status);
        if (waiting == 0) break;
        std::uint64_t n = 0;
        MPI_Recv(&n, 1, MPI_UINT64_T, status.MPI_SOURCE, kProgressTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        const auto from = static_cast<std::size_t>(status.MPI_SOURCE);
        counted[from] = n;
        counted_all[from] = n == samples_of(status.MPI_SOURCE);
      }
      done = traced_all;
      for (int r = 1; r < size; ++r) {
        int arrived = 0;
        std::vector<MPI_Request>& requests = rows_received[static_cast<std::size_t>(r)];
        MPI_Testall(static_cast<int>(requests.size()), requests.data(), &arrived, MPI_STATUSES_IGNORE);
        done = done && arrived != 0 && counted_all[static_cast<std::size_t>(r)];
      }
      std::uint64_t total = 0;
      for (const std::uint64_t n : counted) total += n;
      if (total > reported && on_samples) on_samples(total - reported);
      reported = std::max(reported, total);
      if (!done) std::this_thread::sleep_for(kPoll);
    }
  } else {
    std::uint64_t sent = 0;
    auto last = std::chrono::steady_clock::now();
    while (!finished.load(std::memory_order_acquire)) {
      std::this_thread::sleep_for(kPoll);
      if (std::chrono::steady_clock::now() - last < kProgressPeriod) continue;
      last = std::chrono::steady_clock::now();
      const std::uint64_t n = traced.load(std::memory_order_relaxed);
      if (n != sent) MPI_Send(&n, 1, MPI_UINT64_T, 0, kProgressTag, MPI_COMM_WORLD);
      sent = n;
    }
  }
  tracer.join();
  if (error) std::rethrow_exception(error);
  if (!job.is_root()) {
    std::vector<std::unique_ptr<RowsType>> mine;
    std::vector<MPI_Request> rows_sent(planes.size(), MPI_REQUEST_NULL);
    for (std::size_t p = 0; p < planes.size(); ++p) {
      mine.push_back(std::make_unique<RowsType>(rank, size, width, height, planes[p].floats));
      if (mine.back()->rows() > 0)
        MPI_Isend(planes[p].row(rank, width), 1, mine.back()->type(), 0, planes[p].tag, MPI_COMM_WORLD, &rows_sent[p]);
    }
    const std::uint64_t total = samples_of(rank);
    MPI_Send(&total, 1, MPI_UINT64_T, 0, kProgressTag, MPI_COMM_WORLD);
    for (MPI_Request& request : rows_sent) wait(request);
  }
  return image;
}

FrameExchange::~FrameExchange() { wait(request_); }

void FrameExchange::send(core::ImageRgb8 image) {
  wait(request_);
  sending_ = std::move(image);
  MPI_Isend(sending_.pixels.data(), static_cast<int>(sending_.pixels.size()), MPI_UINT8_T, 0, kFrameTag, MPI_COMM_WORLD,
            &request_);
}

core::ImageRgb8 FrameExchange::receive(int frame, int width, int height) {
  core::ImageRgb8 image(width, height);
  MPI_Request request = MPI_REQUEST_NULL;
  MPI_Irecv(image.pixels.data(), static_cast<int>(image.pixels.size()), MPI_UINT8_T, frame % job_.size(), kFrameTag,
            MPI_COMM_WORLD, &request);
  wait(request);
  return image;
}

}  // namespace tripsitter::cluster
