// What cobra studio costs a run (target: streaming at >= 30 Hz slows a lockstep run by < 10 %):
// the whole two-needle puncturing procedure on the lockstep clock as fast as the CPU goes, side
// by side in the same process, interleaved repetitions:
//  - WithoutStudio: as `cobra run apps/puncturing` runs it;
//  - WithStudio: with the Robot Visualizer Bridge recording (30 frames per simulated s: a live
//    run records for /api/recording) and the server streaming to one WebSocket client that reads
//    every frame (as `cobra run --studio --pace 0` with one browser open).
// Counters: realtime_factor = simulated s per wall s; cpu_realtime_factor = per CPU s of the
// process (the server's and the client's threads included); run_thread_realtime_factor = per CPU s
// of the run's own thread (what the bridge costs the run, whatever the machine's other load);
// client_fps = frames the client received per wall s (first to last frame); published = snapshots the bridge published.
// Three interleaved pairs of rows: read the median and the worst of each side.

#include <benchmark/benchmark.h>

#include <atomic>
#include <chrono>
#include <thread>

#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>

#include "cobra/run/runner.hpp"
#include "cobra/studio/bridge.hpp"
#include "cobra/studio/server.hpp"

#include "app_speed.hpp"

namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;

// CPU time of the calling thread [s] (the lockstep run's steps all run on it).
double threadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

cobra::run::RunOptions procedure() {
  cobra::run::RunOptions options;
  options.app = std::string(COBRA_SOURCE_DIR) + "/apps/puncturing";
  options.scenario = std::string(COBRA_SOURCE_DIR) + "/apps/puncturing/scenarios/two_needles";
  return options;
}

// Reads every message of the server's WebSocket until `stop`, counting frames; `seconds`: from the
// first frame to the last.
void readFrames(unsigned short port, const std::string& token, std::atomic<bool>& stop, std::atomic<long>& frames,
                double& seconds) {
  std::chrono::steady_clock::time_point first{}, last{};
  asio::io_context io;
  websocket::stream<tcp::socket> ws(io);
  ws.next_layer().connect({asio::ip::make_address("127.0.0.1"), port});
  ws.handshake("127.0.0.1", "/ws?token=" + token);
  beast::get_lowest_layer(ws).non_blocking(false);
  while (!stop.load()) {
    beast::flat_buffer buffer;
    beast::error_code error;
    ws.read(buffer, error);
    if (error) return;
    const std::string text = beast::buffers_to_string(buffer.data());
    if (text.rfind("{\"type\":\"frame\"", 0) == 0) {
      last = std::chrono::steady_clock::now();
      if (frames.fetch_add(1) == 0) first = last;
      seconds = std::chrono::duration<double>(last - first).count();
    }
    if (text.rfind("{\"type\":\"end\"", 0) == 0) return;
  }
}

void BM_Procedure(benchmark::State& state, bool studio) {
  double simulated = 0.0, wall = 0.0, cpu = 0.0, thread_cpu = 0.0, client_fps = 0.0, published = 0.0;
  bool completed = true;
  for (auto _ : state) {
    cobra::run::RunOptions options = procedure();
    cobra::studio::BridgeOptions recording;
    recording.record = true;
    cobra::studio::VisualizerBridge bridge(recording);
    std::unique_ptr<cobra::studio::Server> server;
    std::atomic<bool> stop{false};
    std::atomic<long> frames{0};
    double streamed = 0.0;  // s
    std::thread client;
    if (studio) {
      server = std::make_unique<cobra::studio::Server>(bridge, cobra::studio::ServerOptions{});
      client = std::thread(readFrames, server->port(), server->token(), std::ref(stop), std::ref(frames), std::ref(streamed));
      options.observer = &bridge;
    }
    const double cpu_started = cobra::bench::processCpuSeconds();
    const double thread_started = threadCpuSeconds();
    const auto started = std::chrono::steady_clock::now();
    const cobra::run::RunResult result = cobra::run::runApp(options);
    wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    cpu = cobra::bench::processCpuSeconds() - cpu_started;
    thread_cpu = threadCpuSeconds() - thread_started;
    simulated = result.duration;
    completed = completed && result.completed();
    if (studio) {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));  // the end message reaches the client
      stop = true;
      server.reset();
      client.join();
      client_fps = streamed > 0.0 ? static_cast<double>(frames.load() - 1) / streamed : 0.0;
      published = static_cast<double>(bridge.stats().published);
    }
    state.SetIterationTime(wall);
  }
  if (!completed) state.SkipWithError("the procedure did not complete");
  state.counters["simulated_s"] = simulated;
  state.counters["realtime_factor"] = wall > 0.0 ? simulated / wall : 0.0;
  state.counters["cpu_realtime_factor"] = cpu > 0.0 ? simulated / cpu : 0.0;
  state.counters["run_thread_realtime_factor"] = thread_cpu > 0.0 ? simulated / thread_cpu : 0.0;
  if (studio) {
    state.counters["client_fps"] = client_fps;
    state.counters["published"] = published;
  }
}

// Interleaved: without, with, without, with, ... (a machine that slows down slows both).
const bool kRegistered = [] {
  for (int repetition = 0; repetition < 3; ++repetition)
    for (const bool studio : {false, true})
      benchmark::RegisterBenchmark(studio ? "Procedure/WithStudio" : "Procedure/WithoutStudio", BM_Procedure, studio)
          ->Iterations(1)
          ->UseManualTime()
          ->Unit(benchmark::kSecond);
  return true;
}();

}  // namespace

BENCHMARK_MAIN();
