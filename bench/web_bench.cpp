// The web front end under load (bench/RESULTS.md, *Web front end*):
//  - BM_SseViewersVersusAnswering: cpp-httplib 0.11 with Server-Sent Events holds one worker
//    thread per open event stream; with N viewers connected, does a plain request still get an
//    answer? (the library's default pool, and a pool of 32)
//  - BM_PollingViewers: the design chosen — short polling with a sequence number, one request per
//    connection — with V viewers on live charts of a 1,000-machine synthetic shop for 20 s, each
//    doing what machine.js does (live every 1 s, machine detail every 2 s) plus 10 overview
//    viewers (first 100 machines sorted, every 2 s). Reports the server's CPU (process CPU minus
//    the client threads' own), request latency and the age of the newest live value on arrival.
//  - BM_PasswordHash: one argon2id hash at the users' cost (what a login costs the server).
#include <httplib.h>
#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <mutex>
#include <random>
#include <thread>
#include <vector>

#include <benchmark/benchmark.h>
#include <nlohmann/json.hpp>

#include "trueaxis/web/access_db.hpp"
#include "trueaxis/web/password_hash.hpp"
#include "trueaxis/web/synthetic_shop.hpp"
#include "trueaxis/web/web_server.hpp"

namespace {

using namespace trueaxis;
using Clock = std::chrono::steady_clock;

double NowUnixS() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}
double ThreadCpuS() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}
double ProcessCpuS() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec) * 1e-6;
}
double Percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(p * static_cast<double>(v.size() - 1))];
}

// ---- SSE: N open event streams, then one plain request ----
void BM_SseViewersVersusAnswering(benchmark::State& state) {
  const int viewers = static_cast<int>(state.range(0));
  const int pool = static_cast<int>(state.range(1));  // 0: the library's default pool
  for (auto _ : state) {
    httplib::Server svr;
    if (pool > 0) svr.new_task_queue = [pool] { return new httplib::ThreadPool(static_cast<std::size_t>(pool)); };
    std::atomic<bool> stop{false};
    std::atomic<int> streams{0};
    svr.Get("/events", [&](const httplib::Request&, httplib::Response& res) {
      ++streams;
      res.set_chunked_content_provider("text/event-stream", [&](std::size_t, httplib::DataSink& sink) {
        if (stop.load()) return false;
        const std::string ev = "data: {\"t\": 1}\n\n";
        sink.write(ev.data(), ev.size());
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
        return true;
      });
    });
    svr.Get("/ping", [](const httplib::Request&, httplib::Response& res) { res.set_content("pong", "text/plain"); });
    const int port = svr.bind_to_any_port("127.0.0.1");
    std::thread server([&] { svr.listen_after_bind(); });
    std::vector<std::thread> clients;
    for (int i = 0; i < viewers; ++i)
      clients.emplace_back([&, port] {
        httplib::Client c("127.0.0.1", port);
        c.set_read_timeout(30, 0);
        c.Get("/events", [&](const char*, std::size_t) { return !stop.load(); });
      });
    // Until every viewer's stream is open, or no more open for 2 s (the pool is full).
    for (int last = -1, still = 0; streams.load() < viewers && still < 20; ++still) {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      if (streams.load() != last) last = streams.load(), still = 0;
    }
    state.counters["streams_open"] = streams.load();
    httplib::Client probe("127.0.0.1", port);
    probe.set_connection_timeout(3, 0);
    probe.set_read_timeout(3, 0);
    const auto t0 = Clock::now();
    auto r = probe.Get("/ping");
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    state.counters["answered"] = r && r->status == 200 ? 1 : 0;
    state.counters["ping_ms"] = ms;
    stop = true;
    svr.stop();
    server.join();
    for (auto& c : clients) c.join();
  }
}
BENCHMARK(BM_SseViewersVersusAnswering)
    ->ArgsProduct({{4, 7, 8, 16, 31, 32}, {0, 32}})
    ->ArgNames({"viewers", "pool"})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// ---- polling: V viewers of a 1,000-machine shop ----
void BM_PollingViewers(benchmark::State& state) {
  const int viewers = static_cast<int>(state.range(0));
  const int overview_viewers = 10;
  const double duration_s = 20;
  const auto dir = std::filesystem::temp_directory_path() / ("trueaxis_web_bench_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  for (auto _ : state) {
    web::AccessDb access((dir / "users.db").string());
    if (!access.FindUser("viewer")) access.AddUser("viewer", web::Role::kViewer, "viewer-pass-1", web::HashCost::kMinimum);
    web::SyntheticShop shop(1000);
    shop.Start(1.0);
    web::WebServerOptions o;
    o.port = 0;
    web::WebServer server(shop, access, o);
    server.Start();
    const int port = server.port();

    std::mutex m;
    std::vector<double> latency_ms, age_s;
    std::atomic<long> requests{0}, failures{0};
    std::atomic<double> client_cpu_s{0};
    const auto end = Clock::now() + std::chrono::duration<double>(duration_s);
    const double cpu0 = ProcessCpuS();
    const auto wall0 = Clock::now();
    auto viewer = [&](int k, bool overview) {
      const double cpu_start = ThreadCpuS();
      httplib::Client c("127.0.0.1", port);
      c.set_read_timeout(10, 0);
      auto login = c.Post("/api/login", R"({"user":"viewer","password":"viewer-pass-1"})", "application/json");
      if (!login || login->status != 200) {
        ++failures;
        std::fprintf(stderr, "login failed: %s\n", login ? std::to_string(login->status).c_str() : httplib::to_string(login.error()).c_str());
        return;
      }
      const std::string set = login->get_header_value("Set-Cookie");
      const httplib::Headers h{{"Cookie", set.substr(0, set.find(';'))}};
      char id[8];
      std::snprintf(id, sizeof id, "m%04d", 1 + (k * 37) % 1000);
      const std::string base = std::string("/api/machines/") + id;
      std::uint64_t after = 0;
      std::vector<double> my_latency, my_age;
      // Spread the viewers over the second, like browsers opened at different times.
      auto next = Clock::now() + std::chrono::milliseconds(1000 * k / (overview ? overview_viewers : viewers));
      // A simulated browser (hundreds at once, each its own thread ending at `end`), not a service
      // of the program: a plain deadline loop, not core::PeriodicThread.
      for (int tick = 0; Clock::now() < end; ++tick) {
        std::this_thread::sleep_until(next);
        next += std::chrono::seconds(overview ? 2 : 1);
        std::vector<std::string> paths;
        if (overview) paths.push_back("/api/machines?sort=max_temp&order=desc&limit=100");
        else {
          paths.push_back(base + "/live?after=" + std::to_string(after));
          if (tick % 2 == 0) paths.push_back(base);
        }
        for (const auto& p : paths) {
          const auto t0 = Clock::now();
          auto r = c.Get(p, h);
          my_latency.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
          ++requests;
          if (!r || r->status != 200) {
            ++failures;
            std::fprintf(stderr, "%s failed: %s\n", p.c_str(), r ? std::to_string(r->status).c_str() : httplib::to_string(r.error()).c_str());
            continue;
          }
          if (p.find("/live") != std::string::npos) {
            const auto j = nlohmann::json::parse(r->body);
            after = j["last_seq"].get<std::uint64_t>();
            if (!j["samples"].empty()) my_age.push_back(NowUnixS() - j["samples"].back()["t"].get<double>());
          }
        }
      }
      std::lock_guard lock(m);
      latency_ms.insert(latency_ms.end(), my_latency.begin(), my_latency.end());
      age_s.insert(age_s.end(), my_age.begin(), my_age.end());
      client_cpu_s = client_cpu_s + (ThreadCpuS() - cpu_start);
    };
    std::vector<std::thread> threads;
    for (int k = 0; k < viewers; ++k) threads.emplace_back(viewer, k, false);
    for (int k = 0; k < overview_viewers; ++k) threads.emplace_back(viewer, k, true);
    for (auto& t : threads) t.join();
    const double wall = std::chrono::duration<double>(Clock::now() - wall0).count();
    const double server_cpu = ProcessCpuS() - cpu0 - client_cpu_s.load();
    server.Stop();
    shop.Stop();
    state.counters["requests_per_s"] = static_cast<double>(requests.load()) / wall;
    state.counters["failures"] = static_cast<double>(failures.load());
    state.counters["server_cpu_pct_of_1_core"] = 100 * server_cpu / wall;
    state.counters["clients_cpu_pct_of_1_core"] = 100 * client_cpu_s.load() / wall;
    state.counters["latency_p50_ms"] = Percentile(latency_ms, 0.5);
    state.counters["latency_p99_ms"] = Percentile(latency_ms, 0.99);
    state.counters["latency_max_ms"] = Percentile(latency_ms, 1.0);
    state.counters["value_age_p50_s"] = Percentile(age_s, 0.5);
    state.counters["value_age_p99_s"] = Percentile(age_s, 0.99);
    state.counters["value_age_max_s"] = Percentile(age_s, 1.0);
  }
  std::filesystem::remove_all(dir);
}
BENCHMARK(BM_PollingViewers)->Arg(100)->Arg(200)->Arg(500)->ArgNames({"viewers"})->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

void BM_PasswordHash(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(web::HashPassword("some password 1", web::HashCost::kInteractive));
}
BENCHMARK(BM_PasswordHash)->Unit(benchmark::kMillisecond)->Iterations(5);

}  // namespace

BENCHMARK_MAIN();
