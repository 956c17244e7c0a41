#include <tripsitter/render/embree.h>

#include <embree3/rtcore.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include <tripsitter/core/parallel.h>

namespace tripsitter::render {

struct EmbreeScene::State {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  ~State() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

std::string to_string(EmbreePacket p) {
  switch (p) {
    case EmbreePacket::k1: return "single rays";
    case EmbreePacket::k8: return "8-ray packets";
    case EmbreePacket::k16: return "16-ray packets";
  }
  return "?";
}

std::string embree_version() { return RTC_VERSION_STRING; }

EmbreeScene::EmbreeScene(const PathScene& scene, int threads) : scene_(scene), state_(std::make_unique<State>()) {
  const std::string config = "threads=" + std::to_string(core::thread_count(threads));
  state_->device = rtcNewDevice(config.c_str());
  if (!state_->device) throw std::runtime_error("Embree: cannot create a device");
  state_->scene = rtcNewScene(state_->device);
  rtcSetSceneBuildQuality(state_->scene, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry geometry = rtcNewGeometry(state_->device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                                                4 * sizeof(float), scene.size()));
  for (std::size_t i = 0; i < scene.size(); ++i) {
    const Vec3f& c = scene.center(static_cast<std::uint32_t>(i));
    vertices[4 * i + 0] = c.x;
    vertices[4 * i + 1] = c.y;
    vertices[4 * i + 2] = c.z;
    vertices[4 * i + 3] = scene.radius(static_cast<std::uint32_t>(i));
  }
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(state_->scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(state_->scene);
  if (rtcGetDeviceError(state_->device) != RTC_ERROR_NONE) throw std::runtime_error("Embree: the scene did not build");
}

EmbreeScene::~EmbreeScene() = default;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Packets of W rays over blocks of 4 x (W / 4) pixels.
template <int W, class RayHitW>
void trace_block(RTCScene scene, const PathScene& spheres, const ThinLensCamera& camera, const PrimarySettings& s,
                 int col0, int row0, core::ImageRgb8& image, RTCIntersectContext& context,
                 void (*intersect)(const int*, RTCScene, RTCIntersectContext*, RayHitW*)) {
  alignas(64) int valid[W];
  alignas(64) RayHitW rh;
  Ray rays[W];
  for (int k = 0; k < W; ++k) {
    const int col = col0 + k % 4, row = row0 + k / 4;
    valid[k] = col < s.width && row < s.height ? -1 : 0;
    rays[k] = camera.centre_ray(col < s.width ? col : s.width - 1, row < s.height ? row : s.height - 1);
    rh.ray.org_x[k] = rays[k].origin.x;
    rh.ray.org_y[k] = rays[k].origin.y;
    rh.ray.org_z[k] = rays[k].origin.z;
    rh.ray.dir_x[k] = rays[k].dir.x;
    rh.ray.dir_y[k] = rays[k].dir.y;
    rh.ray.dir_z[k] = rays[k].dir.z;
    rh.ray.tnear[k] = 0.0f;
    rh.ray.tfar[k] = kInf;
    rh.ray.time[k] = 0.0f;
    rh.ray.mask[k] = 0xffffffffu;
    rh.ray.id[k] = 0;
    rh.ray.flags[k] = 0;
    rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
  }
  intersect(valid, scene, &context, &rh);
  for (int k = 0; k < W; ++k) {
    if (!valid[k] || rh.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID) continue;
    const int col = col0 + k % 4, row = row0 + k / 4;
    shade_primary(spheres, rays[k], {rh.ray.tfar[k], rh.hit.primID[k]},
                  &image.pixels[3 * (static_cast<std::size_t>(row) * static_cast<std::size_t>(s.width) +
                                     static_cast<std::size_t>(col))]);
  }
}

}  // namespace

core::ImageRgb8 EmbreeScene::render_primary(const ThinLensCamera& camera, const PrimarySettings& s,
                                            EmbreePacket packet) const {
  core::ImageRgb8 image(s.width, s.height);
  RTCScene scene = state_->scene;
  if (packet == EmbreePacket::k1) {
    core::parallel_for(0, s.height, s.threads, [&](int row) {
      for (int col = 0; col < s.width; ++col) {
        const Ray ray = camera.centre_ray(col, row);
        SphereHit hit;
        if (!intersect(ray, 0.0f, kInf, hit)) continue;
        shade_primary(scene_, ray, hit,
                      &image.pixels[3 * (static_cast<std::size_t>(row) * static_cast<std::size_t>(s.width) +
                                         static_cast<std::size_t>(col))]);
      }
    });
    return image;
  }
  const int block_rows = packet == EmbreePacket::k8 ? 2 : 4;
  const int blocks_x = (s.width + 3) / 4;
  core::parallel_for(0, (s.height + block_rows - 1) / block_rows, s.threads, [&](int block_row) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    for (int bx = 0; bx < blocks_x; ++bx) {
      if (packet == EmbreePacket::k8)
        trace_block<8, RTCRayHit8>(scene, scene_, camera, s, 4 * bx, block_row * 2, image, context, rtcIntersect8);
      else
        trace_block<16, RTCRayHit16>(scene, scene_, camera, s, 4 * bx, block_row * 4, image, context, rtcIntersect16);
    }
  });
  return image;
}

bool EmbreeScene::intersect(const Ray& ray, float t_min, float t_max, SphereHit& hit) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  rh.ray = {ray.origin.x, ray.origin.y, ray.origin.z, t_min, ray.dir.x, ray.dir.y, ray.dir.z, 0.0f, t_max,
            0xffffffffu, 0, 0};
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(state_->scene, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  hit = {rh.ray.tfar, rh.hit.primID};
  return true;
}

}  // namespace tripsitter::render
