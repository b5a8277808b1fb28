// bdinterp_bench: where bounded-distortion in-betweens sit between the cheapest interpolation (a
// linear vertex blend) and the cost of a single Newton step (the "floor": one numeric Cholesky
// factorisation + one solve of the interior cotan Laplacian, symbolic analysis reused).
//
//   bdinterp_bench [--sizes=5000,50000,500000] [--big=1000000] [--busy=1000,5000] [--reps=5]
//                  [google benchmark flags]
//
// Meshes: jittered grids of a 2:1 bar with random diagonals; the target bends the bar by 270 degrees
// after stretching it 1.5 x 0.6 (conformal distortion K up to ~3.7). Every BD frame is checked for
// max |2 pi - angle sum| <= 1e-10. --big sizes only get floor, warm frame and memory.
// After the Google Benchmark output a summary table gives the medians and the ratios to the floor,
// then the busy-machine rows (busy.h) for the --busy sizes (--busy= for none).
#include <benchmark/benchmark.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bdinterp/baselines.h"
#include "bdinterp/distortion.h"
#include "bdinterp/interpolator.h"
#include "busy.h"
#include "flatten/flatten.h"
#include "mesh/mesh.h"
#include "blend/metric_blend.h"
#include "parallel/parallel.h"
#include "test_meshes.h"

namespace bd = bdinterp;

namespace {

constexpr double kTolerance = 1e-10;

struct BenchMesh {
  bd::Positions source, target;
  bd::Faces F;
};

// (2 ny + 1) x (ny + 1) jittered grid over [0, 2] x [0, 1], random diagonals, counter-clockwise.
BenchMesh make_mesh(int approx_vertices, unsigned seed = 7) {
  const int ny = std::max(2, static_cast<int>(std::lround(std::sqrt(approx_vertices / 2.0))));
  const bd::testing::TestMesh grid = bd::testing::jittered_grid(2 * ny, ny, 2.0, 1.0, seed);
  BenchMesh m;
  m.source = grid.V;
  m.F = grid.F;
  // Target: stretch 1.5 x 0.6 (K = 2.5), then bend the bar's centre line into 3/4 of a circle
  // (radius 0.64 at the centre line, so K reaches ~3.7 on the inner side).
  const double angle = 1.5 * 3.14159265358979323846, length = 2 * 1.5;
  const double radius = length / angle;
  m.target.resize(m.source.rows(), 2);
  for (int v = 0; v < m.source.rows(); ++v) {
    const double x = 1.5 * m.source(v, 0), y = 0.6 * (m.source(v, 1) - 0.5);
    const double a = x / radius, r = radius - y;
    m.target.row(v) << r * std::sin(a), radius - r * std::cos(a);
  }
  return m;
}

// Everything benchmarked on one mesh, built on first use.
struct Case {
  BenchMesh mesh;
  std::unique_ptr<bd::Interpolator> interp;
  std::unique_ptr<bd::ArapInterpolator> arap;
  std::unique_ptr<bd::Mesh> topo;
  std::vector<bd::Piece> pieces;
  std::unique_ptr<bd::Flattener> floor_solver;
  double max_k = 0;
  double slider_t = 0, slider_dt = 0.01;
};

std::map<int, std::unique_ptr<Case>>& cases() {
  static std::map<int, std::unique_ptr<Case>> c;
  return c;
}

Case& get_case(int n) {
  auto& c = cases()[n];
  if (!c) {
    c = std::make_unique<Case>();
    c->mesh = make_mesh(n);
    c->interp = std::make_unique<bd::Interpolator>(
        std::vector<bd::Positions>{c->mesh.source, c->mesh.target}, c->mesh.F);
    const Eigen::VectorXd K = bd::conformal_distortion(c->mesh.source, c->mesh.target, c->mesh.F);
    c->max_k = K.maxCoeff();
  }
  return *c;
}

void check_accuracy(benchmark::State& state, const bd::FrameStats& st) {
  if (!(st.residual <= kTolerance)) {
    char msg[128];
    std::snprintf(msg, sizeof msg, "residual %.3g > %.0e", st.residual, kTolerance);
    state.SkipWithError(msg);
  }
}

int vertices_of(benchmark::State& state) { return static_cast<int>(state.range(0)); }

// One numeric factorisation + one solve of the interior cotan Laplacian of the source.
void BM_Floor(benchmark::State& state) {
  Case& c = get_case(vertices_of(state));
  if (!c.floor_solver) {
    c.topo = std::make_unique<bd::Mesh>(c.mesh.F, static_cast<int>(c.mesh.source.rows()));
    c.pieces = bd::split_into_disks(*c.topo);
    c.floor_solver = std::make_unique<bd::Flattener>(c.pieces[0].mesh);
  }
  bd::Flattener& fl = *c.floor_solver;
  fl.assemble_hessian(bd::squared_edge_lengths(c.pieces[0].mesh, c.mesh.source),
                      Eigen::VectorXd::Zero(c.mesh.source.rows()));
  bd::SparseCholesky& chol = *fl.cholesky();
  Eigen::VectorXd b = Eigen::VectorXd::Ones(fl.num_interior()), x(fl.num_interior());
  // The thread settings of a frame (Interpolator calls): without them CHOLMOD's OpenMP regions of 4
  // threads on the 2 cores made the 50k floor 73-103 ms instead of 50-68 ms.
  const bd::parallel::ThreadLimit limit(0);
  for (auto _ : state) {
    chol.factorize();
    chol.solve(b.data(), x.data());
    benchmark::DoNotOptimize(x.data());
  }
  state.counters["vertices"] = static_cast<double>(c.mesh.source.rows());
}

void BM_Linear(benchmark::State& state) {
  Case& c = get_case(vertices_of(state));
  double t = 0.3;
  for (auto _ : state) {
    bd::Positions X = bd::linear_interpolate(c.mesh.source, c.mesh.target, t);
    benchmark::DoNotOptimize(X.data());
    t = t > 0.9 ? 0.1 : t + 0.01;
  }
}

// ARAP (Alexa et al.): per-face rotations + one prefactored Poisson solve per frame.
void BM_Poisson(benchmark::State& state) {
  Case& c = get_case(vertices_of(state));
  if (!c.arap) c.arap = std::make_unique<bd::ArapInterpolator>(c.mesh.source, c.mesh.target, c.mesh.F);
  double t = 0.3;
  for (auto _ : state) {
    bd::Positions X = c.arap->at(t);
    benchmark::DoNotOptimize(X.data());
    t = t > 0.9 ? 0.1 : t + 0.01;
  }
}

// Newton steps, factorisations and chord steps per frame, as benchmark counters.
struct StepCounter {
  double iterations = 0, factorizations = 0, chords = 0, frames = 0;
  void add(benchmark::State& state, const bd::FrameStats& st) {
    iterations += st.iterations;
    factorizations += st.factorizations;
    chords += st.chord_steps;
    frames += 1;
    check_accuracy(state, st);
  }
  void report(benchmark::State& state) const {
    state.counters["newton"] = iterations / frames;
    state.counters["factor"] = factorizations / frames;
    state.counters["chord"] = chords / frames;
  }
};

// A new t with nothing cached but the symbolic analysis.
void BM_Cold(benchmark::State& state) {
  Case& c = get_case(vertices_of(state));
  bd::Positions out(c.mesh.source.rows(), 2);
  const double ts[] = {0.5, 0.3, 0.7, 0.15, 0.85};
  int k = 0;
  StepCounter steps;
  for (auto _ : state) {
    c.interp->forget();
    const double t = ts[k++ % 5];
    c.interp->blend_into(Eigen::Vector2d(1 - t, t), out);
    steps.add(state, c.interp->last_stats());
  }
  steps.report(state);
}

// A slider dragged by 0.01 per frame, back and forth over [0, 1].
void BM_Warm(benchmark::State& state) {
  Case& c = get_case(vertices_of(state));
  bd::Positions out(c.mesh.source.rows(), 2);
  auto next = [&] {
    if (c.slider_t + c.slider_dt > 1.0 + 1e-12 || c.slider_t + c.slider_dt < -1e-12) c.slider_dt = -c.slider_dt;
    c.slider_t += c.slider_dt;
    return c.slider_t;
  };
  for (int k = 0; k < 3; ++k) {  // history for the predictor (not timed)
    const double t = next();
    c.interp->blend_into(Eigen::Vector2d(1 - t, t), out);
  }
  StepCounter steps;
  for (auto _ : state) {
    const double t = next();
    c.interp->blend_into(Eigen::Vector2d(1 - t, t), out);
    steps.add(state, c.interp->last_stats());
  }
  steps.report(state);
}

// Baking 101 frames t = 0, 0.01, ..., 1 with state.range(1) threads; time per frame.
void BM_Bake(benchmark::State& state) {
  Case& c = get_case(vertices_of(state));
  const int nf = 101;
  std::vector<double> ts(nf);
  for (int j = 0; j < nf; ++j) ts[j] = j / double(nf - 1);
  bd::Positions out(c.mesh.source.rows() * nf, 2);
  c.interp->set_threads(static_cast<int>(state.range(1)));
  double facts = 0, chords = 0, runs = 0;
  for (auto _ : state) {
    c.interp->forget();
    c.interp->frames(ts, out);
    const bd::FrameStats& st = c.interp->last_stats();
    facts += st.factorizations;
    chords += st.chord_steps;
    runs += 1;
    check_accuracy(state, st);
  }
  c.interp->set_threads(0);
  state.counters["factor"] = facts / (runs * nf);
  state.counters["chord"] = chords / (runs * nf);
  state.SetItemsProcessed(state.iterations() * nf);
}

// Peak resident memory (bytes) of a fresh process that builds the Interpolator and computes a cold
// frame and 5 warm frames; measured in a forked child so the sizes do not pollute each other.
double peak_memory_bytes(int n) {
  int fd[2];
  if (pipe(fd) != 0) return -1;
  const pid_t pid = fork();
  if (pid == 0) {
    close(fd[0]);
    {
      BenchMesh m = make_mesh(n);
      bd::Interpolator I({m.source, m.target}, m.F);
      bd::Positions out(m.source.rows(), 2);
      for (int k = 0; k <= 5; ++k) I.blend_into(Eigen::Vector2d(1 - 0.4 - 0.01 * k, 0.4 + 0.01 * k), out);
    }
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    const double bytes = 1024.0 * ru.ru_maxrss;
    if (write(fd[1], &bytes, sizeof bytes) != sizeof bytes) _exit(1);
    _exit(0);
  }
  close(fd[1]);
  double bytes = -1;
  if (read(fd[0], &bytes, sizeof bytes) != sizeof bytes) bytes = -1;
  close(fd[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  return bytes;
}

// Collects the medians while printing as usual.
class Collector : public benchmark::ConsoleReporter {
 public:
  struct Entry {
    double ms = 0;
    std::map<std::string, double> counters;
    bool error = false;
  };
  std::map<std::string, Entry> medians;  // "Warm/5000" -> median

  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      if (r.error_occurred) medians[key(r)].error = true;
      if (r.aggregate_name != "median" && !(r.run_type == Run::RT_Iteration && r.repetitions <= 1)) continue;
      Entry& e = medians[key(r)];
      e.ms = r.GetAdjustedRealTime();  // time unit is ms
      for (const auto& [name, c] : r.counters) e.counters[name] = c.value;
      if (r.counters.count("items_per_second")) e.counters["items_per_second"] = r.counters.at("items_per_second");
    }
    ConsoleReporter::ReportRuns(runs);
  }

 private:
  static std::string key(const Run& r) { return r.run_name.function_name.substr(3) + "/" + r.run_name.args; }
};

struct Options {
  std::vector<int> sizes{5000, 50000, 500000}, big, busy{1000, 5000};
  int reps = 5;
  std::vector<char*> rest;  // for Google Benchmark
};

std::vector<int> parse_list(const char* s) {
  std::vector<int> out;
  for (const char* p = s; *p;) {
    out.push_back(std::atoi(p));
    while (*p && *p != ',') ++p;
    if (*p == ',') ++p;
  }
  return out;
}

Options parse_options(int argc, char** argv) {
  Options o;
  o.rest.push_back(argv[0]);
  for (int i = 1; i < argc; ++i) {
    if (!std::strncmp(argv[i], "--sizes=", 8)) o.sizes = parse_list(argv[i] + 8);
    else if (!std::strncmp(argv[i], "--big=", 6)) o.big = parse_list(argv[i] + 6);
    else if (!std::strncmp(argv[i], "--reps=", 7)) o.reps = std::atoi(argv[i] + 7);
    else if (!std::strncmp(argv[i], "--busy=", 7)) o.busy = parse_list(argv[i] + 7);
    else o.rest.push_back(argv[i]);
  }
  return o;
}

void register_benchmarks(const Options& o) {
  auto reg = [&](const char* name, void (*fn)(benchmark::State&), int n, int threads = -1) {
    auto* b = benchmark::RegisterBenchmark(name, fn);
    if (threads >= 0) b->Args({n, threads}); else b->Arg(n);
    b->Unit(benchmark::kMillisecond)->Repetitions(o.reps)->ReportAggregatesOnly(true)->UseRealTime();
    if (n >= 200000) b->Iterations(n >= 800000 ? 1 : 3);
    else b->MinTime(n >= 20000 ? 0.3 : 0.2);
  };
  for (int n : o.sizes) {
    reg("BM_Floor", BM_Floor, n);
    reg("BM_Linear", BM_Linear, n);
    reg("BM_Poisson", BM_Poisson, n);
    reg("BM_Cold", BM_Cold, n);
    reg("BM_Warm", BM_Warm, n);
    if (n < 200000) {
      reg("BM_Bake", BM_Bake, n, 1);
      reg("BM_Bake", BM_Bake, n, 2);
    }
  }
  for (int n : o.big) {
    reg("BM_Floor", BM_Floor, n);
    reg("BM_Warm", BM_Warm, n);
  }
}

// One summary row: the medians of size n's benchmarks and their ratios to the floor.
void print_row(const Collector& collector, int n, double memory) {
  auto get = [&](const std::string& name) -> const Collector::Entry* {
    auto it = collector.medians.find(name + "/" + std::to_string(n));
    return it == collector.medians.end() ? nullptr : &it->second;
  };
  auto ms = [&](const std::string& name) { const auto* e = get(name); return e ? e->ms : NAN; };
  auto counter = [&](const std::string& name, const char* c) {
    const auto* e = get(name);
    return e && e->counters.count(c) ? e->counters.at(c) : NAN;
  };
  const Case& c = *cases()[n];
  const double floor_ms = ms("Floor"), warm = ms("Warm"), cold = ms("Cold");
  double bake_ms = NAN;
  auto it = collector.medians.find("Bake/" + std::to_string(n) + "/2");
  if (it != collector.medians.end() && it->second.counters.count("items_per_second"))
    bake_ms = 1000.0 / it->second.counters.at("items_per_second");
  bool err = false;
  for (const auto& [k, e] : collector.medians)
    if (e.error && k.find("/" + std::to_string(n)) != std::string::npos) err = true;
  std::printf("%9ld %6.2f %9.3f %9.3f %9.3f %9.3f %11.3f %11.3f %7.2f %7.2f %9.0f %9.0f %9.2f %9.2f %8.0f%s\n",
              static_cast<long>(c.mesh.source.rows()), c.max_k, ms("Linear"), ms("Poisson"), floor_ms, cold,
              warm, bake_ms, cold / floor_ms, warm / floor_ms, 1000.0 / warm, 1000.0 / bake_ms,
              counter("Cold", "newton"), counter("Warm", "newton"),
              memory / static_cast<double>(c.mesh.source.rows()), err ? "  ACCURACY FAILED" : "");
}

}  // namespace

int main(int argc, char** argv) {
  const bench::MakeInterpolator make = [](int n) {
    const BenchMesh m = make_mesh(n);
    return std::make_unique<bd::Interpolator>(std::vector<bd::Positions>{m.source, m.target}, m.F);
  };
  bench::compete(argc, argv, make);
  Options o = parse_options(argc, argv);
  // Memory first, from a small parent process.
  std::map<int, double> memory;
  for (int n : o.sizes) memory[n] = peak_memory_bytes(n);
  for (int n : o.big) memory[n] = peak_memory_bytes(n);
  register_benchmarks(o);
  int rargc = static_cast<int>(o.rest.size());
  benchmark::Initialize(&rargc, o.rest.data());
  Collector collector;
  benchmark::RunSpecifiedBenchmarks(&collector);

  std::printf("\nSummary (medians of %d repetitions; times in ms; every BD frame checked: residual <= 1e-10)\n", o.reps);
  std::printf("%9s %6s %9s %9s %9s %9s %11s %11s %7s %7s %9s %9s %9s %9s %8s\n", "vertices", "K_max",
              "linear", "poisson", "floor", "cold", "warm", "bake/frame", "cold/fl", "warm/fl", "warm_fps",
              "bake_fps", "newton_c", "newton_w", "peak_B/v");
  for (const auto* list : {&o.sizes, &o.big})
    for (int n : *list) print_row(collector, n, memory[n]);
  std::printf("columns: cold/fl, warm/fl = frame time / floor (targets <= 4, <= 1.5); newton_c/_w = Newton "
              "steps per cold/warm frame (chord steps included);\n         bake = frames(ts) with 2 "
              "threads, 101 frames; peak_B/v = peak RSS of a fresh process (build + 6 frames) per vertex.\n");
  if (!o.busy.empty()) bench::print_busy_rows(o.busy, std::max(o.reps, 15), make);
  benchmark::Shutdown();
  return 0;
}
