// Typed 32-bit element ids and per-element containers shared by every core module.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace seam::core {

using Vec3 = Eigen::Vector3d;
using Vec2 = Eigen::Vector2d;

/// a.x b.y - a.y b.x: the z component of the cross product, twice the signed area of the
/// triangle (0, a, b) (positive when it turns counter-clockwise).
inline double cross2(const Vec2& a, const Vec2& b) {
  return a.x() * b.y() - a.y() * b.x();
}
/// Twice the signed area of the triangle (o, a, b).
inline double cross2(const Vec2& o, const Vec2& a, const Vec2& b) {
  return cross2(a - o, b - o);
}

/// "No index": the all-ones 32-bit value, for an absent vertex, chart, slot or entry in the
/// plain index arrays (typed ids have their own, StrongId::kInvalidValue, the same value).
inline constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

/// "No path", "not reached", "no bound yet": lengths and distances start here.
inline constexpr double kInf = std::numeric_limits<double>::infinity();

/// A typed index into one kind of mesh element. The all-ones value means "none".
/// Distinct tags make passing a FaceId where a VertexId is expected a compile error.
template <class Tag>
class StrongId {
 public:
  static constexpr std::uint32_t kInvalidValue = std::numeric_limits<std::uint32_t>::max();

  constexpr StrongId() = default;
  constexpr explicit StrongId(std::uint32_t value) : value_(value) {}
  constexpr explicit StrongId(std::size_t value) : value_(static_cast<std::uint32_t>(value)) {}

  static constexpr StrongId invalid() { return StrongId(); }
  constexpr std::uint32_t value() const { return value_; }
  constexpr std::size_t index() const { return value_; }
  constexpr bool valid() const { return value_ != kInvalidValue; }

  friend constexpr bool operator==(StrongId a, StrongId b) = default;
  friend constexpr auto operator<=>(StrongId a, StrongId b) = default;

 private:
  std::uint32_t value_ = kInvalidValue;
};

using VertexId = StrongId<struct VertexTag>;
using HalfedgeId = StrongId<struct HalfedgeTag>;
using EdgeId = StrongId<struct EdgeTag>;
using FaceId = StrongId<struct FaceTag>;

/// A vector indexed by one kind of id (`VertexData<double>` is one value per vertex).
template <class Id, class T>
class IdVector {
 public:
  IdVector() = default;
  explicit IdVector(std::size_t size, const T& value = T()) : data_(size, value) {}

  T& operator[](Id id) { return data_[id.index()]; }
  const T& operator[](Id id) const { return data_[id.index()]; }
  std::size_t size() const { return data_.size(); }
  bool empty() const { return data_.empty(); }
  void resize(std::size_t size, const T& value = T()) { data_.resize(size, value); }
  void assign(std::size_t size, const T& value) { data_.assign(size, value); }
  std::vector<T>& raw() { return data_; }
  const std::vector<T>& raw() const { return data_; }
  auto begin() { return data_.begin(); }
  auto end() { return data_.end(); }
  auto begin() const { return data_.begin(); }
  auto end() const { return data_.end(); }

 private:
  std::vector<T> data_;
};

template <class T>
using VertexData = IdVector<VertexId, T>;
template <class T>
using HalfedgeData = IdVector<HalfedgeId, T>;
template <class T>
using EdgeData = IdVector<EdgeId, T>;
template <class T>
using FaceData = IdVector<FaceId, T>;

/// A triangle as three vertex indices, counter-clockwise seen from outside.
using Triangle = std::array<std::uint32_t, 3>;

/// An indexed triangle list as it comes from a file, before welding and validation.
struct IndexedMesh {
  std::vector<Vec3> positions;
  std::vector<Triangle> triangles;
};

}  // namespace seam::core

template <class Tag>
struct std::hash<seam::core::StrongId<Tag>> {
  std::size_t operator()(seam::core::StrongId<Tag> id) const noexcept {
    return std::hash<std::uint32_t>()(id.value());
  }
};
