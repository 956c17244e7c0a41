#include <tripsitter/scene/scene.h>

namespace tripsitter::scene {

const char* material_name(MaterialType type) {
  switch (type) {
    case MaterialType::kLambertian: return "lambertian";
    case MaterialType::kMetal: return "metal";
    case MaterialType::kDielectric: return "dielectric";
  }
  return "unknown";
}

}  // namespace tripsitter::scene
