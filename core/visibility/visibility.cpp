#include "core/visibility/visibility.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>
#include <thread>

#include "core/timing.h"

namespace seam::core {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct DeviceDeleter {
  void operator()(RTCDevice d) const { rtcReleaseDevice(d); }
};
struct SceneDeleter {
  void operator()(RTCScene s) const { rtcReleaseScene(s); }
};
using Device = std::unique_ptr<std::remove_pointer_t<RTCDevice>, DeviceDeleter>;
using Scene = std::unique_ptr<std::remove_pointer_t<RTCScene>, SceneDeleter>;

// The mesh as one Embree triangle geometry (float32, as the BVH stores it).
Result<Scene> build_scene(RTCDevice device, const HalfedgeMesh& mesh) {
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                               3 * sizeof(float), mesh.num_vertices()));
  auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                 3 * sizeof(unsigned), mesh.num_faces()));
  if (vertices == nullptr || indices == nullptr) {
    rtcReleaseGeometry(geometry);
    return make_error(ErrorCode::kSolverFailed, "Embree could not allocate the scene's buffers");
  }
  for (std::uint32_t v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3& p = mesh.position(VertexId(v));
    for (int k = 0; k < 3; ++k) vertices[3 * v + k] = static_cast<float>(p[k]);
  }
  for (std::uint32_t f = 0; f < mesh.num_faces(); ++f) {
    const auto c = mesh.face_vertices(FaceId(f));
    for (int k = 0; k < 3; ++k) indices[3 * f + k] = c[static_cast<std::size_t>(k)].value();
  }
  rtcCommitGeometry(geometry);
  Scene scene(rtcNewScene(device));
  rtcAttachGeometry(scene.get(), geometry);
  rtcReleaseGeometry(geometry);
  rtcSetSceneBuildQuality(scene.get(), RTC_BUILD_QUALITY_MEDIUM);
  rtcCommitScene(scene.get());
  if (rtcGetDeviceError(device) != RTC_ERROR_NONE) {
    return make_error(ErrorCode::kSolverFailed, "Embree could not build the ray-casting scene");
  }
  return scene;
}

bool occluded(RTCScene scene, const Vec3& origin, const Vec3& dir, double tfar) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray{};
  ray.org_x = static_cast<float>(origin.x());
  ray.org_y = static_cast<float>(origin.y());
  ray.org_z = static_cast<float>(origin.z());
  ray.dir_x = static_cast<float>(dir.x());
  ray.dir_y = static_cast<float>(dir.y());
  ray.dir_z = static_cast<float>(dir.z());
  ray.tnear = 0.0f;
  ray.tfar = static_cast<float>(tfar);
  ray.mask = 0xFFFFFFFFu;
  rtcOccluded1(scene, &context, &ray);
  return ray.tfar < 0.0f;  // Embree sets tfar to -inf on a hit
}

// A fixed set of unit directions around +z, cosine-distributed (a Fibonacci spiral on the
// disc lifted to the hemisphere): the same pattern for every face, so results are repeatable.
std::vector<Vec3> hemisphere(int n) {
  std::vector<Vec3> out;
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double r = std::sqrt((i + 0.5) / n);
    const double phi = golden * i;
    out.emplace_back(r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0, 1.0 - r * r)));
  }
  return out;
}

// An orthonormal frame (t, b, n) around unit n.
std::pair<Vec3, Vec3> frame(const Vec3& n) {
  const Vec3 a = std::abs(n.x()) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
  const Vec3 t = n.cross(a).normalized();
  return {t, n.cross(t)};
}

struct FaceRays {
  const HalfedgeMesh& mesh;
  RTCScene scene;
  std::vector<Vec3> views;  // unit directions towards the cameras
  std::vector<Vec3> pattern;
  double offset = 0;
  double ao_distance = 0;

  // seen and openness of face f.
  std::pair<double, double> cast(std::uint32_t f) const {
    const auto c = mesh.face_vertices(FaceId(f));
    const Vec3 a = mesh.position(c[0]), b = mesh.position(c[1]), d = mesh.position(c[2]);
    const Vec3 cross = (b - a).cross(d - a);
    const double len = cross.norm();
    if (!(len > 0)) return {0.0, 1.0};
    const Vec3 n = cross / len;
    const Vec3 origin = (a + b + d) / 3.0 + offset * n;
    double seen = 0;
    for (const Vec3& to_camera : views) {
      const double cosine = n.dot(to_camera);
      if (cosine > seen && !occluded(scene, origin, to_camera, std::numeric_limits<double>::infinity())) seen = cosine;
    }
    double open = 1;
    if (!pattern.empty()) {
      const auto [t, bt] = frame(n);
      int free = 0;
      for (const Vec3& p : pattern) free += !occluded(scene, origin, p.x() * t + p.y() * bt + p.z() * n, ao_distance);
      open = static_cast<double>(free) / static_cast<double>(pattern.size());
    }
    return {seen, open};
  }
};

// The unit vector along a finite non-zero v. Scaled by its largest |component| first: the
// squared norm of (1e200, 1e200, 1e200) overflows to infinity (the "unit" vector came out 0,
// so no face was seen) and that of (1e-200, 1e-200, 1e-200) underflows to 0.
Vec3 unit_direction(const Vec3& v) {
  const Vec3 scaled = v / v.cwiseAbs().maxCoeff();
  return scaled / scaled.norm();
}

Status check(const VisibilityOptions& options) {
  for (const Vec3& v : options.views) {
    if (!v.allFinite() || v.cwiseAbs().maxCoeff() == 0) {
      return make_error(ErrorCode::kInvalidArgument, "a view direction must be finite and non-zero");
    }
  }
  if (options.ambient_occlusion && (options.ao_rays < 1 || options.ao_rays > 1024)) {
    return make_error(ErrorCode::kInvalidArgument, "ao_rays must be 1..1024");
  }
  if (!(options.ao_distance > 0 && options.ao_distance <= 10)) {
    return make_error(ErrorCode::kInvalidArgument, "ao_distance must be in (0, 10]");
  }
  return Ok{};
}

}  // namespace

Result<Visibility> compute_visibility(const HalfedgeMesh& mesh, const VisibilityOptions& options,
                                      const CancelToken& cancel) {
  const auto start = StageClock::now();
  if (auto valid = check(options); !valid.ok()) return valid.take_error();
  Visibility out;
  if (options.views.empty() && !options.ambient_occlusion) return out;
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (std::uint32_t v = 0; v < mesh.num_vertices(); ++v) {
    lo = lo.cwiseMin(mesh.position(VertexId(v)));
    hi = hi.cwiseMax(mesh.position(VertexId(v)));
  }
  const double diagonal = mesh.num_vertices() > 0 ? (hi - lo).norm() : 1.0;
  Device device(rtcNewDevice("threads=1,verbose=0"));
  if (!device) return make_error(ErrorCode::kSolverFailed, "Embree could not start a device");
  SEAM_TRY(Scene scene, build_scene(device.get(), mesh));
  FaceRays rays{mesh, scene.get(), {}, {}, 1e-5 * diagonal, options.ao_distance * diagonal};
  for (const Vec3& v : options.views) rays.views.push_back(-unit_direction(v));
  if (options.ambient_occlusion) rays.pattern = hemisphere(options.ao_rays);

  const std::size_t faces = mesh.num_faces();
  if (!options.views.empty()) out.seen = FaceData<double>(faces, 0.0);
  if (options.ambient_occlusion) out.openness = FaceData<double>(faces, 1.0);
  std::atomic<std::size_t> next{0};
  std::atomic<bool> stopped{false};
  auto work = [&] {
    std::uint32_t poll = 0;
    for (std::size_t f = next++; f < faces && !stopped; f = next++) {
      if (cancel.poll(poll)) stopped = true;
      const auto [seen, open] = rays.cast(static_cast<std::uint32_t>(f));
      if (!options.views.empty()) out.seen[FaceId(static_cast<std::uint32_t>(f))] = seen;
      if (options.ambient_occlusion) out.openness[FaceId(static_cast<std::uint32_t>(f))] = open;
    }
  };
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < std::max(1u, options.threads); ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  if (stopped || cancel.is_cancelled()) return cancelled_error("visibility");
  out.rays = faces * (rays.views.size() + rays.pattern.size());
  out.ms = ms_since(start);
  return out;
}

std::vector<double> hiding_multipliers(const HalfedgeMesh& mesh, const Visibility& visibility, double strength) {
  std::vector<double> out(mesh.num_edges(), 1.0);
  for (std::uint32_t e = 0; e < mesh.num_edges(); ++e) {
    const HalfedgeId h = HalfedgeMesh::halfedge(EdgeId(e));
    double seen = 0, open = 1;
    bool any = false;
    for (const HalfedgeId side : {h, HalfedgeMesh::twin(h)}) {
      const FaceId f = mesh.face(side);
      if (!f.valid()) continue;
      if (!visibility.seen.empty()) seen = std::max(seen, visibility.seen[f]);
      if (!visibility.openness.empty()) open = any ? std::min(open, visibility.openness[f]) : visibility.openness[f];
      any = true;
    }
    double m = 1.0 + strength * seen;
    if (!visibility.openness.empty()) m *= 1.0 + strength * open;
    out[e] = m;
  }
  return out;
}

}  // namespace seam::core
