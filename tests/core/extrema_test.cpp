#include "core/extrema/extrema.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "core/mesh/topology.h"
#include "core/paths/geodesic.h"
#include "extrema_fixtures.h"
#include "fixture_mesh.h"
#include "fixtures.h"
#include "test_data.h"

namespace seam_extrema_test {

using namespace seam::core;
namespace fx = seam::fixtures;

namespace {

ExtremaResult detect(const HalfedgeMesh& mesh, const ExtremaOptions& options = {}) {
  auto result = detect_extrema(mesh, options);
  REQUIRE_MESSAGE(result.ok(), (result.ok() ? "" : result.error().message));
  return std::move(result).value();
}

// Every found tip lies within `tolerance` of an expected tip and every expected tip has
// exactly one found tip near it: the same tips, no more, no fewer.
void check_same_tips(const HalfedgeMesh& mesh, const std::vector<Extremum>& found, const std::vector<Vec3>& expected,
                     double tolerance) {
  CHECK(found.size() == expected.size());
  std::vector<int> hits(expected.size(), 0);
  for (const Extremum& e : found) {
    const Vec3& p = mesh.position(e.vertex);
    std::size_t best = 0;
    for (std::size_t i = 1; i < expected.size(); ++i) {
      if ((p - expected[i]).norm() < (p - expected[best]).norm()) best = i;
    }
    INFO("tip " << e.vertex.value() << " at " << p.transpose() << ", prominence " << e.prominence);
    REQUIRE(!expected.empty());
    CHECK((p - expected[best]).norm() <= tolerance);
    ++hits[best];
  }
  for (std::size_t i = 0; i < expected.size(); ++i) {
    INFO("expected tip " << i << " at " << expected[i].transpose());
    CHECK(hits[i] == 1);
  }
}

std::vector<VertexId> vertices_of(const std::vector<Extremum>& extrema) {
  std::vector<VertexId> v;
  for (const auto& e : extrema) v.push_back(e.vertex);
  return v;
}

// Built once per test run: marching tetrahedra on a fine grid is not free under sanitizers.
const fx::ShapeWithTips& ball() {
  static const fx::ShapeWithTips shape = fx::six_spike_ball(0.06, /*with_bump=*/true);
  return shape;
}
const fx::ShapeWithTips& hand() {
  static const fx::ShapeWithTips shape = fx::capsule_hand(0.05);
  return shape;
}

}  // namespace

TEST_CASE("extrema: options out of range are refused with kInvalidArgument") {
  const HalfedgeMesh mesh = fx::build_fixture(fx::icosphere(1));
  for (double bad : {-0.1, std::nan(""), std::numeric_limits<double>::infinity()}) {
    auto r = find_extrema(mesh, {.min_protrusion = bad});
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == ErrorCode::kInvalidArgument);
  }
  auto r = find_extrema(mesh, {.samples = 1});
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == ErrorCode::kInvalidArgument);
  CHECK(r.error().message.find("samples") != std::string::npos);
}

TEST_CASE("extrema: a round shape has no protrusion") {
  // The estimate's wiggles on a sphere stay far below the default threshold (measured
  // largest prominence 0.02 here), and a sphere is not made of protrusions.
  const HalfedgeMesh mesh = fx::build_fixture(fx::icosphere(4));
  const auto result = detect(mesh);
  CHECK(result.extrema.empty());
  CHECK(result.stats.components == 1);
  CHECK(result.stats.local_maxima > 0);  // the wiggles exist; the filter removes them
}

TEST_CASE("extrema: min_protrusion 0 keeps every local maximum of the AGD, each a strict local maximum") {
  const HalfedgeMesh mesh = fx::build_fixture(fx::icosphere(3));
  const auto result = detect(mesh, {.min_protrusion = 0, .max_count = 0, .min_separation = 0});
  CHECK(result.extrema.size() == result.stats.local_maxima);
  auto field = average_geodesic_distance(mesh, ExtremaOptions{}.samples);
  REQUIRE(field.ok());
  for (const auto& e : result.extrema) {
    mesh.for_each_outgoing(e.vertex, [&](HalfedgeId h) {
      const VertexId u = mesh.head(h);
      const double fu = (*field)[u], fv = (*field)[e.vertex];
      CHECK((fu < fv || (fu == fv && e.vertex < u)));
    });
  }
  // Prominences are sorted, most prominent first, and exactly one maximum (the highest) has
  // no saddle.
  for (std::size_t i = 1; i < result.extrema.size(); ++i) {
    CHECK(result.extrema[i - 1].prominence >= result.extrema[i].prominence);
  }
  CHECK(std::count_if(result.extrema.begin(), result.extrema.end(), [](const Extremum& e) { return !e.saddle.valid(); }) == 1);
}

TEST_CASE("extrema: spikes on a sphere, exactly those tips and not the wart") {
  const auto& shape = ball();
  const HalfedgeMesh mesh = fx::build_fixture(shape.soup);
  const auto result = detect(mesh);
  check_same_tips(mesh, result.extrema, shape.tips, 0.3);
  // The tips stand far above the filter and the wart far below it: a clear gap.
  for (const auto& e : result.extrema) CHECK(e.prominence > 0.15);
  const auto all = detect(mesh, {.min_protrusion = 0, .max_count = 0});
  REQUIRE(all.extrema.size() > shape.tips.size());
  CHECK(all.extrema[shape.tips.size()].prominence < 0.04);
  // The sum over sources is order independent: the thread count does not change a bit.
  const auto one = detect(mesh, {.threads = 1});
  const auto three = detect(mesh, {.threads = 3});
  REQUIRE(one.extrema.size() == three.extrema.size());
  for (std::size_t i = 0; i < one.extrema.size(); ++i) {
    CHECK(one.extrema[i].vertex == three.extrema[i].vertex);
    CHECK(one.extrema[i].prominence == three.extrema[i].prominence);
  }
}

TEST_CASE("extrema: a hand of cylinders on a palm, exactly the five fingertips and the wrist") {
  const auto& shape = hand();
  const HalfedgeMesh mesh = fx::build_fixture(shape.soup);
  const auto result = detect(mesh);
  check_same_tips(mesh, result.extrema, shape.tips, 0.3);
}

TEST_CASE("extrema: invariant to rigid motion and uniform scale") {
  for (const auto* shape : {&ball(), &hand()}) {
    const HalfedgeMesh mesh = fx::build_fixture(shape->soup);
    const auto reference = detect(mesh);
    for (double scale : {0.01, 1.0, 250.0}) {
      const auto moved =
          fx::transformed(*shape, fx::rotation(Vec3(1, -2, 0.5), 2.1), scale, Vec3(3.0, -7.0, 11.0) * scale);
      const HalfedgeMesh moved_mesh = fx::build_fixture(moved.soup);
      const auto result = detect(moved_mesh);
      INFO("scale " << scale);
      // Same vertex ids (vertex numbering is unchanged by the motion) and same prominence.
      CHECK(vertices_of(result.extrema) == vertices_of(reference.extrema));
      REQUIRE(result.extrema.size() == reference.extrema.size());
      for (std::size_t i = 0; i < result.extrema.size(); ++i) {
        CHECK(result.extrema[i].prominence == doctest::Approx(reference.extrema[i].prominence).epsilon(1e-6));
      }
      check_same_tips(moved_mesh, result.extrema, moved.tips, 0.3 * scale);
    }
  }
}

TEST_CASE("extrema: insensitive to the tessellation (remeshed finer, subdivided 1-to-4)") {
  SUBCASE("spiky ball meshed on a finer grid") {
    const auto fine = fx::six_spike_ball(0.045, true);
    const HalfedgeMesh mesh = fx::build_fixture(fine.soup);
    check_same_tips(mesh, detect(mesh).extrema, fine.tips, 0.3);
  }
  SUBCASE("hand meshed on a finer grid") {
    const auto fine = fx::capsule_hand(0.04);
    const HalfedgeMesh mesh = fx::build_fixture(fine.soup);
    check_same_tips(mesh, detect(mesh).extrema, fine.tips, 0.3);
  }
  SUBCASE("spiky ball subdivided 1-to-4 (multi-resolution path), one and two threads bit-identical") {
    const HalfedgeMesh mesh = fx::build_fixture(fx::subdivided(ball().soup));
    REQUIRE(mesh.num_vertices() > 40000);  // large enough for the coarse cell graph
    const auto one = detect(mesh, {.threads = 1});
    const auto two = detect(mesh, {.threads = 2});
    check_same_tips(mesh, one.extrema, ball().tips, 0.3);
    REQUIRE(one.extrema.size() == two.extrema.size());
    for (std::size_t i = 0; i < one.extrema.size(); ++i) {
      CHECK(one.extrema[i].vertex == two.extrema[i].vertex);
      CHECK(one.extrema[i].prominence == two.extrema[i].prominence);  // exact, not approximate
    }
  }
}

TEST_CASE("extrema: per component, each judged against its own area") {
  // The hand, and the ball shrunk 100 times far away: the ball's spikes are tiny against the
  // total area but large against its own, so they are kept.
  const auto small_ball = fx::transformed(ball(), Eigen::Matrix3d::Identity(), 0.01, Vec3(50, 0, 0));
  const auto soup = fx::join(hand().soup, small_ball.soup);
  const HalfedgeMesh mesh = fx::build_fixture(soup);
  const Topology topo = compute_topology(mesh);
  REQUIRE(topo.components.size() == 2);
  const auto result = detect(mesh);
  CHECK(result.stats.components == 2);
  std::vector<Extremum> first, second;
  for (const auto& e : result.extrema) {
    CHECK(e.component == topo.vertex_component[e.vertex]);
    (e.component == 0 ? first : second).push_back(e);
  }
  // Grouped by component, ascending.
  CHECK(std::is_sorted(result.extrema.begin(), result.extrema.end(),
                       [](const Extremum& a, const Extremum& b) { return a.component < b.component; }));
  check_same_tips(mesh, first, hand().tips, 0.3);
  check_same_tips(mesh, second, small_ball.tips, 0.003);
}

TEST_CASE("extrema: max_count keeps the most prominent, isolated vertices are ignored") {
  fx::Soup soup = hand().soup;
  soup.positions.emplace_back(100, 100, 100);  // an isolated vertex
  const HalfedgeMesh mesh = fx::build_fixture(soup);
  const auto all = detect(mesh);
  const auto three = detect(mesh, {.max_count = 3});
  REQUIRE(all.extrema.size() == 6);
  REQUIRE(three.extrema.size() == 3);
  for (std::size_t i = 0; i < 3; ++i) CHECK(three.extrema[i].vertex == all.extrema[i].vertex);
  for (const auto& e : all.extrema) CHECK(e.vertex.index() + 1 < mesh.num_vertices());
  // find_extrema returns the same vertices in the same order.
  auto plain = find_extrema(mesh);
  REQUIRE(plain.ok());
  CHECK(*plain == vertices_of(all.extrema));
}

namespace {

// A box part: an icosphere pushed out onto the cube [-1, 1]^3, scaled and moved.
fx::Soup box_part(double size, const Vec3& at) {
  fx::Soup s = fx::icosphere(2);
  for (auto& p : s.positions) p = p / p.cwiseAbs().maxCoeff() * size + at;
  return s;
}

// A rod part: an icosphere stretched 8:1 along z, scaled and moved.
fx::Soup rod_part(double size, const Vec3& at) {
  fx::Soup s = fx::icosphere(2);
  for (auto& p : s.positions) p = Vec3(p.x(), p.y(), 8 * p.z()) * size + at;
  return s;
}

double geodesic(const HalfedgeMesh& mesh, VertexId a, VertexId b) {
  const EdgeGraph graph = build_edge_graph(mesh);
  auto tree = dijkstra(graph, std::span<const VertexId>(&a, 1));
  REQUIRE(tree.ok());
  return tree->distance[b.index()];
}

}  // namespace

// A plate part: an icosphere pushed out onto the box [-1, 1] x [-0.5, 0.5] x [-0.1, 0.1].
fx::Soup plate_part(double size, const Vec3& at) {
  fx::Soup s = box_part(1, Vec3(0, 0, 0));
  for (auto& p : s.positions) p = Vec3(p.x(), 0.5 * p.y(), 0.1 * p.z()) * size + at;
  return s;
}

TEST_CASE("extrema: small closed parts: boxes and plates get none, a rod its two ends, the body keeps its tips") {
  // The hand and, beside it, 6 boxes, 6 plates and one rod, each well under a quarter of the
  // hand's diagonal.
  fx::Soup soup = hand().soup;
  for (int i = 0; i < 12; ++i) {
    const Vec3 at(4 + 0.5 * (i % 4), 0.5 * (i / 4), 0);
    soup = fx::join(soup, i < 6 ? box_part(0.1, at) : plate_part(0.15, at));
  }
  soup = fx::join(soup, fx::translated(rod_part(0.05, Vec3(0, 0, 0)), Vec3(4, -1, 0)));
  const HalfedgeMesh mesh = fx::build_fixture(soup);
  const Topology topo = compute_topology(mesh);
  REQUIRE(topo.components.size() == 14);
  // Measured without the small-part rule: the prominences the rule separates.
  const auto loose = detect(mesh, {.min_protrusion = 0.0, .small_part = 0});
  double part_max = 0, rod_max = 0;
  for (const auto& e : loose.extrema) {
    if (e.component == 0) continue;
    if (e.component == 13) rod_max = std::max(rod_max, e.prominence);
    else part_max = std::max(part_max, e.prominence);
  }
  MESSAGE("box and plate corners: prominence up to " << part_max << "; rod ends: up to " << rod_max);
  CHECK(part_max < ExtremaOptions{}.small_part_protrusion);
  CHECK(rod_max >= ExtremaOptions{}.small_part_protrusion);

  const auto result = detect(mesh);
  std::vector<Extremum> body, rod;
  for (const auto& e : result.extrema) {
    CHECK((e.component == 0 || e.component == 13));  // no tip on any box or plate
    (e.component == 0 ? body : rod).push_back(e);
  }
  check_same_tips(mesh, body, hand().tips, 0.3);
  REQUIRE(rod.size() == 2);
  CHECK(std::abs(mesh.position(rod[0].vertex).z() - mesh.position(rod[1].vertex).z()) > 0.6);  // both ends
}

TEST_CASE("extrema: never a vertex twice, and kept tips of a component at least min_separation apart") {
  const HalfedgeMesh mesh = fx::build_fixture(fx::join(box_part(1, Vec3(0, 0, 0)), fx::icosphere(3)));
  for (double separation : {0.05, 0.2, 0.5}) {
    CAPTURE(separation);
    const auto result = detect(mesh, {.min_protrusion = 0, .max_count = 0, .min_separation = separation});
    const auto all = detect(mesh, {.min_protrusion = 0, .max_count = 0, .min_separation = 0});
    CHECK(result.extrema.size() <= all.extrema.size());
    if (separation >= 0.2) CHECK(result.extrema.size() < all.extrema.size());
    const Topology topo = compute_topology(mesh);
    for (std::size_t i = 0; i < result.extrema.size(); ++i) {
      for (std::size_t j = i + 1; j < result.extrema.size(); ++j) {
        const Extremum &a = result.extrema[i], &b = result.extrema[j];
        CHECK(a.vertex != b.vertex);
        if (a.component != b.component) continue;
        std::vector<std::uint32_t> comp;
        for (std::uint32_t v = 0; v < mesh.num_vertices(); ++v) {
          if (topo.vertex_component[VertexId(v)] == a.component) comp.push_back(v);
        }
        Eigen::AlignedBox3d box;
        for (auto v : comp) box.extend(mesh.position(VertexId(v)));
        CHECK(geodesic(mesh, a.vertex, b.vertex) >= separation * box.diagonal().norm());
      }
    }
  }
}

TEST_CASE("extrema: the new options out of range are refused") {
  const HalfedgeMesh mesh = fx::build_fixture(fx::tetrahedron());
  for (const ExtremaOptions& bad : {ExtremaOptions{.min_separation = -1}, ExtremaOptions{.small_part = std::nan("")},
                                    ExtremaOptions{.small_part_protrusion = -0.1}}) {
    auto r = detect_extrema(mesh, bad);
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == ErrorCode::kInvalidArgument);
  }
}

TEST_CASE("extrema: a cancelled token stops detection with kCancelled") {
  const HalfedgeMesh mesh = fx::build_fixture(fx::icosphere(3));
  CancelToken token;
  token.cancel();
  auto r = find_extrema(mesh, {}, token);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == ErrorCode::kCancelled);
}

TEST_CASE("extrema: surfaces with boundary and tiny components do not break detection") {
  const auto soup = fx::join(fx::open_cylinder(), fx::translated(fx::tetrahedron(), Vec3(5, 0, 0)));
  const HalfedgeMesh mesh = fx::build_fixture(soup);
  const auto result = detect(mesh);
  CHECK(result.stats.components == 2);
  for (const auto& e : result.extrema) CHECK(e.vertex.index() < mesh.num_vertices());
}

// ---------------------------------------------------------------------------------------
// Real meshes from CGAL's data. Reference vertices were picked by looking at the meshes
// (rendered with the found tips marked) and are defined by a reproducible rule: the extreme
// vertex along a direction, optionally among the vertices satisfying a condition. Every
// found tip must lie on one of the listed protrusions (geodesic distance to its reference
// within the protrusion's tolerance), and every required group (a protrusion, or a foot
// with several toes) must carry at least one found tip.

namespace {

struct Reference {
  const char* name;
  Vec3 direction;
  bool (*filter)(const Vec3&);  // nullptr: every vertex
  int group;         // references with the same positive group are one protrusion; 0: optional
  double tolerance;  // geodesic, as a fraction of sqrt(area)
};

VertexId extreme_vertex(const HalfedgeMesh& mesh, const Reference& ref) {
  VertexId best;
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3& p = mesh.position(VertexId(v));
    if (ref.filter && !ref.filter(p)) continue;
    if (!best.valid() || p.dot(ref.direction) > mesh.position(best).dot(ref.direction)) best = VertexId(v);
  }
  REQUIRE(best.valid());
  return best;
}

double surface_area(const HalfedgeMesh& mesh) {
  double area = 0;
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    const auto v = mesh.face_vertices(FaceId(f));
    area += 0.5 * (mesh.position(v[1]) - mesh.position(v[0])).cross(mesh.position(v[2]) - mesh.position(v[0])).norm();
  }
  return area;
}

void check_real_mesh(const std::string& name, const std::vector<Reference>& refs) {
  const HalfedgeMesh mesh = seam::test_data::load_cgal_halfedge(name);
  const double unit = std::sqrt(surface_area(mesh));
  const auto result = detect(mesh);
  const EdgeGraph graph = build_edge_graph(mesh);
  std::vector<int> found_on(refs.size() + 1, 0);  // per group
  for (const auto& e : result.extrema) {
    // Which protrusion is this tip on? The reference geodesically closest, relative to tolerance.
    int on = -1;
    double best = INFINITY;
    for (std::size_t i = 0; i < refs.size(); ++i) {
      const VertexId source[] = {extreme_vertex(mesh, refs[i])};
      const VertexId target[] = {e.vertex};
      auto tree = dijkstra(graph, source, {.targets = target});
      REQUIRE(tree.ok());
      const double d = tree->distance[e.vertex.index()] / (refs[i].tolerance * unit);
      if (d < best) best = d, on = static_cast<int>(i);
    }
    INFO(name << ": tip " << e.vertex.value() << " at " << mesh.position(e.vertex).transpose() << " prominence "
              << e.prominence << " nearest protrusion " << std::string(refs[on].name));
    CHECK(best <= 1.0);
    if (best <= 1.0) ++found_on[static_cast<std::size_t>(refs[on].group)];
  }
  for (const auto& ref : refs) {
    INFO(name << ": protrusion " << std::string(ref.name));
    if (ref.group > 0) CHECK(found_on[static_cast<std::size_t>(ref.group)] >= 1);
  }
}

}  // namespace

TEST_CASE("extrema: CGAL elephant, tips on the trunk, the four feet and the ears") {
  // y is up, the body runs along x, the trunk is raised, the front foot at +x is lifted.
  // The tail hangs flat against the rump; it is listed so a tip there counts as on a
  // protrusion, but optional (its prominence is below the filter).
  check_real_mesh("elephant",
                  {{"trunk (highest vertex, 691)", Vec3(0, 1, 0), nullptr, 1, 0.1},
                   {"lifted front foot (2169)", Vec3(1, -1, -1), nullptr, 2, 0.1},
                   {"front foot (2029)", Vec3(1, -1, 1), nullptr, 3, 0.1},
                   {"hind foot (2405)", Vec3(-1, -1, 0), nullptr, 4, 0.1},
                   {"hind foot (2548)", Vec3(-1, -1, 1), nullptr, 5, 0.1},
                   {"ear facing +z (1400)", Vec3(0, 0, 1), nullptr, 6, 0.1},
                   {"ear facing -z: lowest x above y = 0 (1530)", Vec3(-1, 0, 0),
                    [](const Vec3& p) { return p.y() > 0; }, 7, 0.1},
                   {"tail: lowest x with -0.25 < y < 0 (1269)", Vec3(-1, 0, 0),
                    [](const Vec3& p) { return p.y() > -0.25 && p.y() < 0; }, 0, 0.1}});
}

TEST_CASE("extrema: CGAL camel, tips on the four legs, the head and the tail") {
  // y is up, the camel faces +z, the hooves rest on y = -0.489 (hind ones at z < -0.2). The
  // tail is a thin strand hanging from the rump; its end is the most negative z at |y| < 0.03.
  check_real_mesh("camel", {{"head: nose, highest z (315)", Vec3(0, 0, 1), nullptr, 1, 0.1},
                            {"tail end (1229)", Vec3(0, 0, -1), [](const Vec3& p) { return std::abs(p.y()) < 0.03; }, 2, 0.1},
                            {"hind hoof +x (8801)", Vec3(1, -10, 0), [](const Vec3& p) { return p.z() < -0.2; }, 3, 0.1},
                            {"hind hoof -x (9212)", Vec3(-1, -10, 0), [](const Vec3& p) { return p.z() < -0.2; }, 4, 0.1},
                            {"front hoof +x (9073)", Vec3(1, -10, 0), [](const Vec3& p) { return p.z() > -0.2; }, 5, 0.1},
                            {"front hoof -x (9494)", Vec3(-1, -10, 0), [](const Vec3& p) { return p.z() > -0.2; }, 6, 0.1}});
}

TEST_CASE("extrema: CGAL dino, tips on the crest, the snout end, the claws and the hind feet") {
  // Each hind foot (at z = -2.04) has two toes, each a tip: one group per foot.
  auto left = [](const Vec3& p) { return p.x() < 0; };
  auto right = [](const Vec3& p) { return p.x() > 0; };
  check_real_mesh("dino", {{"crest: highest y (1663)", Vec3(0, 1, 0), nullptr, 1, 0.1},
                           {"snout end along (0,-1,1) (1628)", Vec3(0, -1, 1), nullptr, 2, 0.1},
                           {"claw +x (3617)", Vec3(1, -0.5, 0), nullptr, 3, 0.1},
                           {"claw -x (3613)", Vec3(-1, -0.5, 0), nullptr, 4, 0.1},
                           {"left foot, outer toe (3547)", Vec3(-1, 0, -3), left, 5, 0.1},
                           {"left foot, inner toe (3528)", Vec3(1, 0, -3), left, 5, 0.1},
                           {"right foot, inner toe (3716)", Vec3(-1, 0, -3), right, 6, 0.1},
                           {"right foot, outer toe (3429)", Vec3(1, 0, -3), right, 6, 0.1}});
}

TEST_CASE("extrema: CGAL hand, a fist: the raised thumb and the wrist") {
  // The fist itself is round; its two protrusions are the thumb (lowest y) and the forearm
  // stub, cut flat at z = -0.5: any vertex of that cut face is its tip, so its tolerance is
  // the face's radius (0.35 of 1.59).
  check_real_mesh("hand", {{"thumb: lowest y (573)", Vec3(0, -1, 0), nullptr, 1, 0.1},
                           {"wrist: lowest z above y = 0.2 (70)", Vec3(0, 0, -1),
                            [](const Vec3& p) { return p.y() > 0.2; }, 2, 0.25}});
}

TEST_CASE("extrema with the caller's topology: the same tips, and a topology of another mesh is refused") {
  const HalfedgeMesh mesh = seam::test_data::load_cgal_halfedge("hand");
  const HalfedgeMesh other = seam::test_data::load_cgal_halfedge("mushroom");
  auto own = detect_extrema(mesh);
  auto given = detect_extrema(mesh, compute_topology(mesh));
  REQUIRE(own.ok());
  REQUIRE(given.ok());
  REQUIRE(own->extrema.size() == given->extrema.size());
  for (std::size_t i = 0; i < own->extrema.size(); ++i) {
    CHECK(own->extrema[i].vertex == given->extrema[i].vertex);
    CHECK(own->extrema[i].prominence == given->extrema[i].prominence);
  }
  auto wrong = detect_extrema(mesh, compute_topology(other));
  REQUIRE_FALSE(wrong.ok());
  CHECK(wrong.error().code == ErrorCode::kInvalidArgument);
}

}  // namespace seam_extrema_test
