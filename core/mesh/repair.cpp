#include "core/mesh/repair.h"

#include <algorithm>
#include <numeric>
#include <tuple>

#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/split_pinched.h"
#include "core/seam/tree_util.h"

namespace seam::core {
namespace {

// The soup while it is repaired: faces over positions, with the maps back to the input.
struct Work {
  std::vector<Vec3> positions;
  std::vector<Triangle> triangles;
  std::vector<std::uint32_t> source;
  std::vector<std::uint32_t> face_source;
  std::vector<std::uint8_t> detached;
};

// Corner 3t + k is the directed edge t[k] -> t[k+1].
using EdgeUse = EdgeCorner;

bool in_range(const Triangle& t, std::size_t n) { return t[0] < n && t[1] < n && t[2] < n; }

std::uint32_t tail(const std::vector<Triangle>& tris, std::uint32_t corner) { return tris[corner / 3][corner % 3]; }

// The corner of `corner`'s face that sits at vertex v (v is one end of the corner's edge).
std::uint32_t corner_at(const std::vector<Triangle>& tris, std::uint32_t corner, std::uint32_t v) {
  return tail(tris, corner) == v ? corner : 3 * (corner / 3) + (corner % 3 + 1) % 3;
}

// Every edge use, grouped by undirected edge and in corner order inside a group, so the
// result depends only on the input order.
std::vector<EdgeUse> edge_uses(const Work& w) { return sorted_edge_uses(w.triangles, w.positions.size()); }

// Calls f(begin, end) for every group of uses of one undirected edge.
template <class F>
void for_each_edge(const std::vector<EdgeUse>& uses, F&& f) {
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i + 1;
    while (j < uses.size() && uses[j].key == uses[i].key) ++j;
    f(i, j);
    i = j;
  }
}

// Gives every vertex one copy per fan, where a fan is the corners at the vertex linked through
// edges of exactly two faces (edges of three or more faces glue nothing). The fan holding the
// vertex's lowest corner keeps it; copies are numbered by vertex, then by the fan's lowest
// corner (split_pinched_vertices' numbering). Returns the vertices that were split.
std::vector<std::uint32_t> split_fans(Work& w) {
  const std::size_t nf = w.triangles.size();
  const std::vector<EdgeUse> uses = edge_uses(w);
  detail::UnionFind fans(3 * nf);
  for_each_edge(uses, [&](std::size_t i, std::size_t j) {
    if (j - i != 2) return;
    const auto a = static_cast<std::uint32_t>(uses[i].key >> 32);
    const auto b = static_cast<std::uint32_t>(uses[i].key & 0xffffffffu);
    for (const std::uint32_t v : {a, b}) {
      fans.unite(corner_at(w.triangles, uses[i].corner, v), corner_at(w.triangles, uses[i + 1].corner, v));
    }
  });
  std::vector<std::uint32_t> roots(3 * nf, kNoFan);
  for (std::uint32_t t = 0; t < nf; ++t) {
    if (!in_range(w.triangles[t], w.positions.size())) continue;
    for (std::uint32_t k = 0; k < 3; ++k) roots[3 * t + k] = fans.find(3 * t + k);
  }
  return split_corner_fans(w.positions, w.source, w.triangles, roots);
}

// Gives face f three vertices of its own.
void detach(Work& w, std::uint32_t f) {
  for (auto& v : w.triangles[f]) {
    const auto copy = static_cast<std::uint32_t>(w.positions.size());
    w.positions.push_back(w.positions[v]);
    w.source.push_back(w.source[v]);
    v = copy;
  }
  w.detached[f] = 1;
}

// After split_fans, an edge of three or more faces is left only where the sheets are joined
// around both of its ends; keep its first two faces there and split off the rest.
std::size_t detach_leftover_non_manifold(Work& w) {
  const std::vector<EdgeUse> uses = edge_uses(w);
  std::size_t detached = 0;
  for_each_edge(uses, [&](std::size_t i, std::size_t j) {
    std::size_t kept = 0;
    for (std::size_t u = i; u < j && j - i > 2; ++u) {
      const std::uint32_t f = uses[u].corner / 3;
      if (w.detached[f]) continue;
      if (kept < 2) {
        ++kept;
        continue;
      }
      detach(w, f);
      ++detached;
    }
  });
  return detached;
}

// Two faces across a two-face edge; parity 1 when they traverse it in the same direction, so
// exactly one of them must be reversed.
struct Link {
  std::uint32_t f, g, parity;
};

std::vector<Link> two_face_links(const Work& w) {
  const std::vector<EdgeUse> uses = edge_uses(w);
  std::vector<Link> links;
  for_each_edge(uses, [&](std::size_t i, std::size_t j) {
    if (j - i != 2) return;
    const std::uint32_t c0 = uses[i].corner, c1 = uses[i + 1].corner;
    links.push_back({c0 / 3, c1 / 3, tail(w.triangles, c0) == tail(w.triangles, c1) ? 1u : 0u});
  });
  return links;
}

// Per sheet, a reversal bit per face that agrees with the spanning tree of a breadth-first
// search from the sheet's lowest face, then inverted where that reverses most of the sheet.
std::vector<std::uint8_t> orientation_flips(const Work& w, const std::vector<Link>& links) {
  const std::size_t nf = w.triangles.size();
  std::vector<std::uint32_t> offset(nf + 1, 0);
  for (const Link& l : links) ++offset[l.f + 1], ++offset[l.g + 1];
  std::partial_sum(offset.begin(), offset.end(), offset.begin());
  std::vector<std::pair<std::uint32_t, std::uint32_t>> adjacent(offset.back());  // (face, parity)
  std::vector<std::uint32_t> fill(offset.begin(), offset.end() - 1);
  for (const Link& l : links) {
    adjacent[fill[l.f]++] = {l.g, l.parity};
    adjacent[fill[l.g]++] = {l.f, l.parity};
  }
  std::vector<std::uint8_t> flip(nf, 0);
  std::vector<std::uint8_t> seen(nf, 0);
  std::vector<std::uint32_t> sheet;
  for (std::uint32_t root = 0; root < nf; ++root) {
    if (seen[root]) continue;
    sheet.assign(1, root);
    seen[root] = 1;
    std::size_t flipped = 0;
    for (std::size_t q = 0; q < sheet.size(); ++q) {
      const std::uint32_t f = sheet[q];
      flipped += flip[f];
      for (std::uint32_t a = offset[f]; a < offset[f + 1]; ++a) {
        const auto [g, parity] = adjacent[a];
        if (seen[g]) continue;
        seen[g] = 1;
        flip[g] = static_cast<std::uint8_t>(flip[f] ^ parity);
        sheet.push_back(g);
      }
    }
    if (2 * flipped > sheet.size()) {
      for (auto f : sheet) flip[f] ^= 1;
    }
  }
  return flip;
}

// Reverses the faces that disagree with their sheet; in a non-orientable sheet, splits off one
// face (the higher id) of every edge whose faces still disagree.
void orient(Work& w, RepairCounts& counts, std::vector<std::uint8_t>& reoriented) {
  const std::vector<Link> links = two_face_links(w);
  const std::vector<std::uint8_t> flip = orientation_flips(w, links);
  for (const Link& l : links) {
    if ((flip[l.f] ^ flip[l.g]) == l.parity || w.detached[l.f] || w.detached[l.g]) continue;
    detach(w, std::max(l.f, l.g));
    ++counts.split_off_faces;
  }
  reoriented.assign(w.triangles.size(), 0);
  for (std::size_t f = 0; f < w.triangles.size(); ++f) {
    if (!flip[f] || w.detached[f]) continue;
    std::swap(w.triangles[f][1], w.triangles[f][2]);
    reoriented[f] = 1;
    ++counts.reoriented_faces;
  }
}

bool degenerate(std::span<const Vec3> positions, const Triangle& t) {
  if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) return true;
  // Exactly zero area, the builder's test: slivers stay.
  return (positions[t[1]] - positions[t[0]]).cross(positions[t[2]] - positions[t[0]]).squaredNorm() == 0.0;
}

}  // namespace

RepairedMesh repair_mesh(std::span<const Vec3> positions, std::span<const Triangle> triangles) {
  RepairedMesh out;
  Work w;
  w.positions.assign(positions.begin(), positions.end());
  w.source.resize(positions.size());
  std::iota(w.source.begin(), w.source.end(), 0u);
  out.input_to_face.assign(triangles.size(), RepairedMesh::kNoFace);
  for (std::uint32_t f = 0; f < triangles.size(); ++f) {
    const Triangle& t = triangles[f];
    if (in_range(t, positions.size()) && degenerate(positions, t)) {
      out.degenerate_faces.push_back(f);
      continue;
    }
    out.input_to_face[f] = static_cast<std::uint32_t>(w.triangles.size());
    w.triangles.push_back(t);
    w.face_source.push_back(f);
  }
  w.detached.assign(w.triangles.size(), 0);
  out.counts.degenerate_faces = out.degenerate_faces.size();

  // Non-manifold edges first: orientation is only defined across two-face edges.
  std::vector<std::uint32_t> ends;  // vertices on non-manifold edges
  const std::vector<EdgeUse> uses = edge_uses(w);
  for_each_edge(uses, [&](std::size_t i, std::size_t j) {
    if (j - i <= 2) return;
    ++out.counts.non_manifold_edges;
    ends.push_back(static_cast<std::uint32_t>(uses[i].key >> 32));
    ends.push_back(static_cast<std::uint32_t>(uses[i].key & 0xffffffffu));
  });
  if (out.counts.non_manifold_edges > 0) {
    std::sort(ends.begin(), ends.end());
    // Vertices split here away from the non-manifold edges were pinched.
    for (auto v : split_fans(w)) out.counts.pinched_vertices += !std::binary_search(ends.begin(), ends.end(), v);
    out.counts.split_off_faces += detach_leftover_non_manifold(w);
  }
  orient(w, out.counts, out.reoriented);
  // Split-off faces and reversed ones may leave vertices pinched.
  out.counts.pinched_vertices += split_fans(w).size();

  out.positions = std::move(w.positions);
  out.triangles = std::move(w.triangles);
  out.vertex_source = std::move(w.source);
  out.face_source = std::move(w.face_source);
  return out;
}

}  // namespace seam::core
