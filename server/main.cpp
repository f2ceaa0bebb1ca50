// seamd: argument dispatch only. Serving lives in seam_server_lib, batch mode in seam_api.
#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <sys/signalfd.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <thread>

#include "api/cli.h"
#include "api/process_env.h"
#include "server/config.h"
#include "server/server.h"

namespace {

// SIGTERM/SIGINT are blocked before seamd starts any thread, so every thread it starts (HTTP,
// workers, and the pools libraries start from them: libgomp behind METIS, OpenBLAS) inherits
// the block, and a signal thread takes them from a signalfd: no handler runs inside library
// code. That matters because METIS (CHOLMOD's nested-dissection ordering) installs its own
// SIGTERM handler, which longjmps, for the length of each call; a SIGTERM handled during one
// crashed the process. Threads a library starts before main (OpenBLAS's pool) do not have the
// signals blocked: seamd re-executes itself once with OPENBLAS_NUM_THREADS=1 when it is unset,
// so there are none, and for any left a handler writes one byte into a pipe that the same
// thread reads. Either way Server::shutdown runs in ordinary code, not in a signal handler.
int stop_pipe[2] = {-1, -1};

extern "C" void on_stop_signal(int) {
  const int saved = errno;
  const char byte = 1;
  [[maybe_unused]] const auto written = write(stop_pipe[1], &byte, 1);
  errno = saved;
}

// Blocks until SIGTERM/SIGINT arrives (through `stop_fd` or the handler's pipe): true; or
// until a zero byte on the pipe says run() ended on its own: false.
bool wait_for_stop(int stop_fd) {
  pollfd fds[2] = {{stop_fd, POLLIN, 0}, {stop_pipe[0], POLLIN, 0}};
  while (true) {
    if (poll(fds, 2, -1) < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    if ((fds[0].revents & POLLIN) != 0) return true;
    if ((fds[1].revents & POLLIN) != 0) {
      char byte = 0;
      if (read(stop_pipe[0], &byte, 1) < 0 && errno == EINTR) continue;
      return byte == 1;
    }
  }
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
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGTERM);
  sigaddset(&stop_signals, SIGINT);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);
  const int stop_fd = signalfd(-1, &stop_signals, SFD_CLOEXEC);
  if (pipe2(stop_pipe, O_CLOEXEC) != 0 || stop_fd < 0) {
    std::cerr << "seamd: cannot create the signal pipe: " << std::strerror(errno) << "\n";
    return 1;
  }

  seam::server::Server server(parsed->config);
  auto port = server.bind();
  if (!port.ok()) {
    std::cerr << seam::api::error_text(port.error()) << "\n";
    return 1;
  }
  std::thread signal_thread([&server, stop_fd] {
    if (wait_for_stop(stop_fd)) server.shutdown();  // false: run() ended on its own
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
    context.reexec_argv = argv;
    // A reader that quits early (`seamd seam in.glb - | head -c 4`) is a failed write, not a kill.
    std::signal(SIGPIPE, SIG_IGN);
    std::ios::sync_with_stdio(false);  // whole assets through cin/cout: no per-character stdio sync
    return seam::api::run_cli(argc - 1, argv + 1, std::cin, std::cout, std::cerr, context);
  }
  // OpenBLAS starts its thread pool when it is loaded, before main, unless
  // OPENBLAS_NUM_THREADS says 1 (seamd uses it single-threaded anyway): executed again with it
  // set, no thread exists that does not block the stop signals (api/process_env.h).
  seam::api::reexec_with(seam::api::ProcessEnv{}, argv);
  return serve(argc, argv);
}
