// Typed errors and Result<T>: core never throws for bad input, it returns an Error.
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace seam::core {

/// Why a core operation refused its input or could not finish. Mapping to strings and
/// HTTP statuses lives in api/ as one exhaustive switch.
enum class ErrorCode {
  kInvalidArgument,          // an option or parameter is out of its documented range
  kEmptyMesh,                // no vertices or no faces
  kIndexOutOfRange,          // a triangle or extremum names a vertex that does not exist
  kNonFinitePosition,        // a coordinate is NaN or infinite
  kDegenerateFace,           // a face repeats a vertex or has zero area
  kNonManifoldEdge,          // an edge shared by three or more faces
  kNonManifoldVertex,        // a vertex whose faces form several fans
  kInconsistentOrientation,  // two faces traverse a shared edge in the same direction
  kTooManyTerminals,         // the exact method was asked for more terminals than it takes
  kTopologyViolation,        // a result failed its own topological check (a cut is not a disc)
  kSolverFailed,             // a linear solve failed (e.g. the matrix is not positive definite)
  kCancelled,                // the cancellation token fired (time budget exceeded)
};

/// An error with a human-readable message that names the offending element, and the
/// first few offending element indices (vertex, edge or face ids, as the code implies).
struct Error {
  ErrorCode code = ErrorCode::kInvalidArgument;
  std::string message;
  std::vector<std::uint32_t> elements;
  /// Named quantities the message states, for callers that should not parse it, e.g.
  /// {"count", 12}, {"limit", 10} for kTooManyTerminals.
  std::vector<std::pair<std::string, std::uint64_t>> values;
};

/// Either a value or an error (core::Error by default; api/ uses its own ApiError).
/// `[[nodiscard]]` so an ignored failure is a warning.
template <class T, class E = Error>
class [[nodiscard]] Result {
 public:
  Result(T value) : state_(std::move(value)) {}  // NOLINT(google-explicit-constructor)
  Result(E error) : state_(std::move(error)) {}  // NOLINT(google-explicit-constructor)

  bool ok() const { return state_.index() == 0; }
  explicit operator bool() const { return ok(); }

  T& value() & { return std::get<0>(state_); }
  const T& value() const& { return std::get<0>(state_); }
  T&& value() && { return std::get<0>(std::move(state_)); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }

  const E& error() const { return std::get<1>(state_); }
  E&& take_error() { return std::get<1>(std::move(state_)); }

 private:
  std::variant<T, E> state_;
};

/// Success without a value.
struct Ok {};
using Status = Result<Ok>;

inline Error make_error(ErrorCode code, std::string message, std::vector<std::uint32_t> elements = {}) {
  return Error{code, std::move(message), std::move(elements), {}};
}

[[noreturn]] inline void assertion_failed(const char* expr, const char* file, int line) {
  std::fprintf(stderr, "SEAM_ASSERT(%s) failed at %s:%d\n", expr, file, line);
  std::abort();
}

}  // namespace seam::core

/// Always-on check of a cheap invariant. A failure is a bug, never an input error.
#define SEAM_ASSERT(expr) \
  ((expr) ? static_cast<void>(0) : ::seam::core::assertion_failed(#expr, __FILE__, __LINE__))

/// Propagate an error from a Result-returning expression: `SEAM_TRY(auto x, f());`
#define SEAM_CONCAT_INNER(a, b) a##b
#define SEAM_CONCAT(a, b) SEAM_CONCAT_INNER(a, b)
#define SEAM_TRY_IMPL(tmp, decl, expr) \
  auto tmp = (expr);                   \
  if (!tmp.ok()) return tmp.take_error(); \
  decl = std::move(tmp).value()
#define SEAM_TRY(decl, expr) SEAM_TRY_IMPL(SEAM_CONCAT(seam_try_, __LINE__), decl, expr)
