#include "core/seam/shrink.h"

#include <algorithm>

namespace seam::core {

Result<ShrinkResult> shrink_tour(const HalfedgeMesh& mesh, const Tour& tour, const CancelToken& cancel) {
  std::vector<std::int32_t> mark(mesh.num_halfedges(), -1);
  std::vector<HalfedgeId> queue;
  queue.reserve(mesh.num_halfedges());
  for (std::size_t i = 0; i < tour.pieces.size(); ++i) {
    for (HalfedgeId h : tour.pieces[i]) {
      // A half-edge on two pieces keeps its first mark; it is queued once.
      if (mark[h.index()] >= 0) continue;
      mark[h.index()] = static_cast<std::int32_t>(i);
      queue.push_back(h);
    }
  }
  ShrinkResult result;
  std::uint32_t polls = 0;
  for (std::size_t head = 0; head < queue.size(); ++head) {
    if (cancel.poll(polls)) return cancelled_error("skeleton shrink");
    const HalfedgeId e = queue[head];
    const HalfedgeId twin = HalfedgeMesh::twin(e);
    if (mesh.is_boundary(e) || mesh.is_boundary(twin)) continue;
    if (mark[twin.index()] < 0) {
      // The twin's face is reached first by this wave: it takes the mark, and its other
      // two half-edges carry it on.
      const HalfedgeId e1 = mesh.next(twin);
      const HalfedgeId e2 = mesh.next(e1);
      mark[twin.index()] = mark[e.index()];
      // A face half-edge may already hold another piece's mark when it lies on the tour;
      // it keeps that mark (the tour is fixed) and the meeting is found when it is popped.
      for (HalfedgeId f : {e1, e2}) {
        if (mark[f.index()] < 0) {
          mark[f.index()] = mark[e.index()];
          queue.push_back(f);
        }
      }
    } else if (mark[twin.index()] != mark[e.index()]) {
      result.skeleton.push_back(HalfedgeMesh::edge(e));
    }
  }
  std::sort(result.skeleton.begin(), result.skeleton.end());
  result.skeleton.erase(std::unique(result.skeleton.begin(), result.skeleton.end()), result.skeleton.end());
  result.face_mark.assign(mesh.num_faces(), -1);
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    const HalfedgeId h = mesh.face_halfedge(FaceId(f));
    // A face carries the mark of the wave that entered it; its half-edges all agree except
    // for tour half-edges, so take the majority of the three.
    const std::int32_t a = mark[h.index()], b = mark[mesh.next(h).index()], c = mark[mesh.prev(h).index()];
    result.face_mark[f] = (a == b || a == c) ? a : b;
  }
  return result;
}

}  // namespace seam::core
