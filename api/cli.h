// The command line's batch mode: `seamd seam ...` and `seamd sample ...` (no HTTP server).
#pragma once

#include <ostream>

namespace seam::api {

/// Runs a CLI subcommand. argv[0] is the subcommand name ("seam" or "sample").
///   seamd seam --mesh FILE(.off|.obj|.glb|.gltf|.drc) [--extrema i,j,k|auto]
///              [--method skeleton|mst|greedy|optimal] [--uv slim|arap|bff|lscm|none]
///              [--weld-epsilon X] [--out cut.glb] [--draco]
///     prints the API's 200 body (without the asset) as JSON on `out`.
///   seamd sample --out sample.glb   writes the bundled procedural sample mesh.
/// Returns the process exit code (0 ok, 1 processing error, 2 usage error); errors are
/// printed as the contract's JSON error body on `err`.
int run_cli(int argc, char** argv, std::ostream& out, std::ostream& err);

}  // namespace seam::api
