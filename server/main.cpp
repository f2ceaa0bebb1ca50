// seamd: argument dispatch only. Serving lives in seam_server_lib, batch mode in seam_api.
#include <pthread.h>

#include <csignal>
#include <cstring>
#include <iostream>
#include <thread>

#include "api/cli.h"
#include "server/config.h"
#include "server/server.h"

namespace {

// SIGTERM/SIGINT are blocked in every thread and taken synchronously by one thread, so the
// handler can call ordinary code (Server::shutdown) instead of being async-signal-safe.
int serve(int argc, char** argv) {
  auto parsed = seam::server::parse_config(argc, argv);
  if (!parsed.ok()) {
    std::cerr << seam::api::error_body(parsed.error()).dump() << "\n";
    return 2;
  }
  if (parsed->help) {
    std::cout << seam::server::help_text();
    return 0;
  }
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGTERM);
  sigaddset(&signals, SIGINT);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  std::signal(SIGPIPE, SIG_IGN);

  seam::server::Server server(parsed->config);
  auto port = server.bind();
  if (!port.ok()) {
    std::cerr << seam::api::error_body(port.error()).dump() << "\n";
    return 1;
  }
  std::thread signal_thread([&server, signals] {
    int sig = 0;
    sigwait(&signals, &sig);
    server.shutdown();
  });
  server.run();
  // run() returns only after shutdown(); the signal thread has already finished then,
  // unless run() failed on its own: wake it so it can be joined.
  if (signal_thread.joinable()) {
    pthread_kill(signal_thread.native_handle(), SIGTERM);
    signal_thread.join();
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 2 && (std::strcmp(argv[1], "seam") == 0 || std::strcmp(argv[1], "sample") == 0)) {
    return seam::api::run_cli(argc - 1, argv + 1, std::cout, std::cerr);
  }
  return serve(argc, argv);
}
