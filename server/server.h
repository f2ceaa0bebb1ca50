// The seam HTTP service (API.md): POST /seam on a bounded worker pool of its own, plus
// /healthz, /readyz, /metrics and /version. A library so that seamd, the end-to-end tests and
// the load benchmark run the same code. httplib stays out of this header (it must not meet
// Eigen in one translation unit before Eigen, see shared/notes/stack.md).
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "api/error.h"
#include "api/pipeline.h"
#include "core/cancel.h"
#include "server/config.h"
#include "server/metrics.h"

namespace seam::server {

/// The computation behind POST /seam. Defaults to api::run_seam_pipeline; tests inject a
/// controllable job to exercise backpressure, budgets and shutdown deterministically.
using SeamJob = std::function<api::ApiResult<api::PipelineOutput>(
    const std::string& asset, api::AssetKind kind, const api::SeamParams& params,
    const api::PipelineLimits& limits, const core::CancelToken& cancel)>;

/// The job that calls api::run_seam_pipeline.
SeamJob pipeline_job();

class Server {
 public:
  /// Builds the server (no socket yet). An empty `job` means pipeline_job().
  explicit Server(ServerConfig config, SeamJob job = {});
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  /// Binds config.bind:config.port (port 0 = ephemeral). Returns the bound port.
  /// Errors: kInternal with the address when the bind fails (in use, bad address).
  api::ApiResult<int> bind();

  /// Serves on the bound socket until shutdown(); returns after every in-flight request
  /// was answered and the worker pool drained. Call bind() first. Blocking.
  void run();

  /// Starts draining: /readyz turns 503, no new connections are accepted, new seam jobs
  /// get 503, in-flight work finishes; work still running after drain_timeout_s is
  /// cancelled (its client gets 504). Thread-safe, idempotent, non-blocking.
  void shutdown();

  /// True between the start of run() and the end of the accept loop.
  bool is_running() const;
  int port() const;
  /// The bound --health-port (-1 when there is none).
  int health_port() const;
  /// A shell line that makes the sample and posts it to this server (printed at start).
  std::string try_line() const;
  const ServerConfig& config() const;
  const Metrics& metrics() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The body of GET /version: service version, build, library versions.
nlohmann::json version_info();

}  // namespace seam::server
