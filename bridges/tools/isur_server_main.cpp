// cobra-isur-server: the local stand-alone I-SUR server of thesis §4.5.7 as its own process.
// Keeps the shared memory segment of an ISURRobotBridge in step with the robot controller over UDP.
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>

#include "cobra/bridges/isur_udp_server.hpp"

namespace {

volatile std::sig_atomic_t g_stop = 0;
void onSignal(int) { g_stop = 1; }

int usage(const char* why) {
  std::fprintf(stderr,
               "cobra-isur-server: %s\n"
               "usage: cobra-isur-server --controller HOST:PORT [--shm /NAME] [--listen HOST:PORT] [--joints N]\n"
               "                         [--tools M] [--period S] [--max-delay S]\n",
               why);
  return 2;
}

bool splitHostPort(const std::string& text, std::string& host, std::uint16_t& port) {
  const auto colon = text.rfind(':');
  if (colon == std::string::npos) return false;
  host = text.substr(0, colon);
  char* end = nullptr;
  const long p = std::strtol(text.c_str() + colon + 1, &end, 10);
  if (*end != '\0' || p < 0 || p > 65535) return false;
  port = static_cast<std::uint16_t>(p);
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  cobra::bridges::IsurUdpServerOptions options;
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    if (i + 1 >= argc) return usage(("missing value after " + flag).c_str());
    const std::string value = argv[++i];
    if (flag == "--controller") {
      if (!splitHostPort(value, options.controller_host, options.controller_port))
        return usage(("--controller " + value + ": give HOST:PORT").c_str());
    } else if (flag == "--listen") {
      if (!splitHostPort(value, options.bind_host, options.bind_port))
        return usage(("--listen " + value + ": give HOST:PORT").c_str());
    } else if (flag == "--shm") {
      options.shm_name = value;
    } else if (flag == "--joints") {
      options.joints = static_cast<std::uint16_t>(std::atoi(value.c_str()));
    } else if (flag == "--tools") {
      options.tools = static_cast<std::uint16_t>(std::atoi(value.c_str()));
    } else if (flag == "--period") {
      options.command_period = std::atof(value.c_str());
    } else if (flag == "--max-delay") {
      options.max_delay = std::atof(value.c_str());
    } else {
      return usage(("unknown option " + flag).c_str());
    }
  }
  try {
    cobra::bridges::IsurUdpServer server(options);
    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
    server.start();
    std::printf("cobra-isur-server: shared memory %s, states on %s, commands to %s:%u\n", options.shm_name.c_str(),
                server.local().text().c_str(), options.controller_host.c_str(), options.controller_port);
    std::fflush(stdout);
    while (g_stop == 0) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    server.stop();
    std::printf("cobra-isur-server: %llu states accepted, %llu rejected\n",
                static_cast<unsigned long long>(server.counters().accepted()),
                static_cast<unsigned long long>(server.counters().rejected()));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cobra-isur-server: %s\n", e.what());
    return 1;
  }
  return 0;
}
