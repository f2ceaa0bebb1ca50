// seamd: argument dispatch only. Serving lives in seam_server_lib, batch mode in seam_api.
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <iostream>
#include <thread>

#include "api/cli.h"
#include "server/config.h"
#include "server/server.h"

namespace {

// SIGTERM/SIGINT: a handler writes one byte into a pipe and a thread that reads the pipe
// calls Server::shutdown, so the shutdown path is ordinary code, not async-signal-safe code.
// (Blocking the signals and taking them with sigwait is not enough: threads that libraries
// start before main, such as OpenBLAS's pool behind CHOLMOD, do not have them blocked, so the
// kernel may hand SIGTERM to one of them, where the default action kills the process, or, for
// PID 1 in a container, drops the signal.) The pipe is the one piece of process-wide state
// here, as signal handlers are process-wide.
int stop_pipe[2] = {-1, -1};

extern "C" void on_stop_signal(int) {
  const int saved = errno;
  const char byte = 1;
  [[maybe_unused]] const auto written = write(stop_pipe[1], &byte, 1);
  errno = saved;
}

int serve(int argc, char** argv) {
  auto parsed = seam::server::parse_config(argc, argv);
  if (!parsed.ok()) {
    std::cerr << seam::api::error_text(parsed.error()) << "\n";
    return 2;
  }
  if (parsed->help) {
    std::cout << seam::server::help_text();
    return 0;
  }
  std::signal(SIGPIPE, SIG_IGN);
  if (pipe2(stop_pipe, O_CLOEXEC) != 0) {
    std::cerr << "seamd: cannot create the signal pipe: " << std::strerror(errno) << "\n";
    return 1;
  }

  seam::server::Server server(parsed->config);
  auto port = server.bind();
  if (!port.ok()) {
    std::cerr << seam::api::error_text(port.error()) << "\n";
    return 1;
  }
  std::thread signal_thread([&server] {
    char byte = 0;
    while (read(stop_pipe[0], &byte, 1) < 0 && errno == EINTR) {
    }
    if (byte == 1) server.shutdown();  // 0: run() ended on its own
  });
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  sigaction(SIGTERM, &action, nullptr);
  sigaction(SIGINT, &action, nullptr);
  server.run();
  // run() returns after shutdown() (the signal thread is done or about to be), or on its own:
  // a zero byte wakes the thread without shutting anything down.
  const char wake = 0;
  [[maybe_unused]] const auto written = write(stop_pipe[1], &wake, 1);
  signal_thread.join();
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 2 && (std::strcmp(argv[1], "seam") == 0 || std::strcmp(argv[1], "batch") == 0 ||
                    std::strcmp(argv[1], "sample") == 0 || std::strcmp(argv[1], "--version") == 0)) {
    seam::api::CliContext context;
    context.version = SEAM_VERSION;
    context.stdout_is_terminal = isatty(STDOUT_FILENO) == 1;
    // A reader that quits early (`seamd seam in.glb - | head -c 4`) is a failed write, not a kill.
    std::signal(SIGPIPE, SIG_IGN);
    std::ios::sync_with_stdio(false);  // whole assets through cin/cout: no per-character stdio sync
    return seam::api::run_cli(argc - 1, argv + 1, std::cin, std::cout, std::cerr, context);
  }
  return serve(argc, argv);
}
