// `lasertwin sweep SCENE --out DIR [--spp 1,4,16,64] [--methods com,steger]
// [--threads N] [--min-detection F] [--quick] [--replot] [--quiet]`: run time against error. Renders the
// scene's laser frames over a ladder of render settings, scans each run with
// each extraction method, evaluates it against ground truth, and writes
// DIR/sweep.csv and DIR/pareto.svg (docs/performance.md, "Run time against error").
//
// Configurations: one factor at a time from the base (the scene's settings
// with the base spp): adaptive sampling off, max_bounces 0 / 1 / 4 (those not
// the scene's), subsurface off, half resolution (the camera binned 2 x 2,
// scene/sensor_binning.h: the same lens and field of view on a quarter of the
// pixels, at the same image level); plus the spp ladder, each with every method
// (the one-factor configurations use the first method). Each configuration
// renders into DIR/runs/<name>/ (replaced if present); its scan outputs and
// evaluation for method M are renamed centers_M/, cloud_M.ply, metrics_M.json,
// report_M.html so that every method's results stay inspectable. The Pareto plot (reading
// sweep.csv, the front, the SVG) is in sweep_pareto.cpp.
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <tuple>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/error.h"
#include "pipeline/eval_metrics.h"
#include "pipeline/eval_report.h"
#include "pipeline/scan.h"
#include "pipeline/svg_plot.h"
#include "render/frame_renderer.h"
#include "scene/sensor_binning.h"
#include "render/frame_writer.h"
#include "render/run_folder.h"
#include "scene/embree_scene.h"
#include "scene/scene_file.h"
#include "tools/lasertwin/command.h"
#include "tools/lasertwin/run_scene_distance.h"
#include "tools/lasertwin/sweep_pareto.h"

namespace lt::cli {
namespace {

namespace fs = std::filesystem;

struct SweepArgs {
  std::string scene;
  std::string out;
  std::string spp;
  std::string methods;
  int threads = 1;
  double min_detection = 0.5;
  bool quick = false;
  bool replot = false;
  bool quiet = false;
};

struct RenderConfig {
  std::string name, factor;
  int spp = 16;
  bool adaptive = true;
  int bounces = 2;
  bool subsurface = true;
  bool half_resolution = false;
  std::vector<ExtractionMethod> methods;
};

struct Row {
  RenderConfig config;
  ExtractionMethod method = ExtractionMethod::kCom;
  int frames = 0;
  double render_wall_ms = 0, render_cpu_ms = 0, ground_truth_ms = 0, scan_wall_ms = 0, scan_cpu_ms = 0;  // per frame
  EvalSummary eval;
};

double CpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}
double WallSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::vector<int> ParseInts(const std::string& text, const std::string& option) {
  std::vector<int> v;
  std::stringstream ss(text);
  for (std::string f; std::getline(ss, f, ',');) {
    if (f.empty() || f.size() > 6 || f.find_first_not_of("0123456789") != std::string::npos || std::stoi(f) < 1) {
      throw InputError(option, "expected positive whole numbers separated by commas, got '" + text + "'");
    }
    v.push_back(std::stoi(f));
  }
  return v;
}

std::vector<RenderConfig> Ladder(const SceneFile& scene, const std::vector<int>& spps,
                                 const std::vector<ExtractionMethod>& methods, bool quick) {
  RenderConfig base;
  base.spp = std::find(spps.begin(), spps.end(), scene.render.spp) != spps.end() ? scene.render.spp : spps.back();
  base.adaptive = scene.render.adaptive_sampling;
  base.bounces = scene.render.max_bounces;
  base.subsurface = scene.render.subsurface;
  base.methods = {methods.front()};
  std::vector<RenderConfig> out;
  for (int s : spps) {
    RenderConfig c = base;
    c.name = "spp" + std::to_string(s);
    c.factor = s == base.spp ? "base" : "spp";
    c.spp = s;
    c.methods = methods;
    out.push_back(c);
  }
  auto vary = [&](const std::string& name, const std::string& factor, auto change) {
    RenderConfig c = base;
    c.name = name;
    c.factor = factor;
    change(c);
    out.push_back(c);
  };
  vary(base.adaptive ? "adaptive_off" : "adaptive_on", "adaptive_sampling", [](RenderConfig& c) { c.adaptive = !c.adaptive; });
  for (int b : quick ? std::vector<int>{0} : std::vector<int>{0, 1, 4}) {
    if (b != base.bounces) vary("bounces" + std::to_string(b), "max_bounces", [b](RenderConfig& c) { c.bounces = b; });
  }
  vary(base.subsurface ? "subsurface_off" : "subsurface_on", "subsurface", [](RenderConfig& c) { c.subsurface = !c.subsurface; });
  vary("half_resolution", "resolution", [](RenderConfig& c) { c.half_resolution = true; });
  return out;
}

// Renders the laser frames of the configuration into `dir`; fills the timings of `row`.
void RenderRun(const SceneFile& original, const RenderConfig& c, int threads, const fs::path& dir, Row* row) {
  nlohmann::json j = original.resolved;
  j["render"]["spp"] = c.spp;
  j["render"]["adaptive_sampling"] = c.adaptive;
  j["render"]["max_bounces"] = c.bounces;
  j["render"]["subsurface"] = c.subsurface;
  j["render"]["threads"] = threads;
  // A camera binned 2 x 2: a quarter of the pixels at the same image level.
  if (c.half_resolution) BinSensorSection(j["sensor"], original.sensor.image_sensor.params(), 2);
  const SceneFile scene = ParseSceneText(j.dump(), original.path.string() + " (" + c.name + ")", original.path.parent_path());
  fs::remove_all(dir);
  RunFolder run(dir, scene.resolved, false);
  WriteFileAtomically(run.dir() / "rig.json", SensorRigToJson(scene.sensor).dump(2) + "\n");
  auto geometry = std::make_shared<SceneGeometry>(LoadSceneGeometry(scene));
  EmbreeScene embree(geometry);
  FrameRenderer renderer(scene, embree);
  for (int i = 0; i < scene.render.frames; ++i) {
    const ShutterFrame sf = scene.sensor.shutter.Frame(i, scene.seed);
    if (!(sf.laser_on || sf.laser_fraction > 0) || scene.sensor.lasers.empty()) continue;
    const double w0 = WallSeconds(), c0 = CpuSeconds();
    RenderedFrame frame = renderer.Render(i);
    row->render_cpu_ms += (CpuSeconds() - c0) * 1e3;
    row->render_wall_ms += (WallSeconds() - w0) * 1e3;
    row->ground_truth_ms += frame.stats.ground_truth_ms;
    run.CompleteFrame(i, WriteFrame(run, frame, i, scene, renderer.seed(), renderer.spp()));
    ++row->frames;
  }
  if (row->frames == 0) throw InputError(original.path.string(), "the scene has no laser frame to sweep");
  row->render_cpu_ms /= row->frames;
  row->render_wall_ms /= row->frames;
  row->ground_truth_ms /= row->frames;
}

// Scans and evaluates the run with one method; keeps its outputs under method-named names.
void ScanAndEvaluate(const fs::path& dir, ExtractionMethod method, int threads, Row* row) {
  ScanOptions o;
  o.extraction.method = method;
  o.extraction.threads = threads;
  const double w0 = WallSeconds(), c0 = CpuSeconds();
  ScanRun(dir, o, [](const std::string&) {});
  row->scan_cpu_ms = (CpuSeconds() - c0) * 1e3 / row->frames;
  row->scan_wall_ms = (WallSeconds() - w0) * 1e3 / row->frames;
  std::string why_not;  // a sweep's runs hold their resolved scene.json
  const RunMetrics m = EvaluateRun(dir, {}, RunSceneDistance(dir, &why_not));
  if (!why_not.empty()) throw std::runtime_error(why_not);
  WriteMetricsJson(dir, m);
  WriteEvalReport(dir, m);
  row->eval = m.total;
  const std::string suffix = std::string("_") + MethodName(method);
  fs::remove_all(dir / ("centers" + suffix));
  fs::rename(dir / "centers", dir / ("centers" + suffix));
  for (const char* f : {"cloud.ply", "metrics.json", "report.html"}) {
    const fs::path p = dir / f;
    if (fs::exists(p)) fs::rename(p, dir / (p.stem().string() + suffix + p.extension().string()));
  }
}

std::string Num(double v, int decimals) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}
std::string Opt(const std::optional<double>& v, int decimals) { return v ? Num(*v, decimals) : ""; }
std::string StatText(const ErrorStats& s, double ErrorStats::*f, int decimals) { return s.n ? Num(s.*f, decimals) : ""; }

std::string Csv(const std::vector<Row>& rows) {
  std::string out =
      "name,factor,spp,adaptive_sampling,max_bounces,subsurface,resolution,method,frames,render_wall_ms,render_cpu_ms,"
      "ground_truth_ms,scan_wall_ms,scan_cpu_ms,center_rms_px,center_p95_px,detection_rate,false_positives,"
      "plane_id_accuracy,point_rms_mm,point_p95_mm,completeness\n";
  for (const Row& r : rows) {
    const RenderConfig& c = r.config;
    out += c.name + "," + c.factor + "," + std::to_string(c.spp) + "," + (c.adaptive ? "on" : "off") + "," +
           std::to_string(c.bounces) + "," + (c.subsurface ? "on" : "off") + "," + (c.half_resolution ? "half" : "full") +
           "," + MethodName(r.method) + "," + std::to_string(r.frames) + "," + Num(r.render_wall_ms, 1) + "," +
           Num(r.render_cpu_ms, 1) + "," + Num(r.ground_truth_ms, 1) + "," + Num(r.scan_wall_ms, 2) + "," +
           Num(r.scan_cpu_ms, 2) + "," + StatText(r.eval.center_px, &ErrorStats::rms, 4) + "," +
           StatText(r.eval.center_px, &ErrorStats::p95, 4) + "," + Opt(r.eval.detection_rate, 4) + "," +
           std::to_string(r.eval.counts.false_positives) + "," + Opt(r.eval.plane_id_accuracy, 4) + "," +
           StatText(r.eval.point_mm, &ErrorStats::rms, 4) + "," + StatText(r.eval.point_mm, &ErrorStats::p95, 4) + "," +
           Opt(r.eval.completeness, 4) + "\n";
  }
  return out;
}

std::vector<ParetoPoint> ParetoPoints(const std::vector<Row>& rows) {
  std::vector<ParetoPoint> out;
  for (const Row& r : rows) {
    if (r.eval.point_mm.n == 0) continue;
    out.push_back({r.config.name + (r.config.methods.size() > 1 ? std::string("/") + MethodName(r.method) : ""),
                   r.render_cpu_ms + r.scan_cpu_ms, r.eval.point_mm.rms, r.eval.detection_rate.value_or(0),
                   ChangesPhysics(r.config.factor)});
  }
  return out;
}

void Run(const SweepArgs& a) {
  if (!(a.min_detection >= 0 && a.min_detection <= 1)) throw InputError("--min-detection", "must be in [0, 1]");
  if (a.replot) {
    const fs::path csv = fs::path(a.out) / "sweep.csv";
    WriteFileAtomically(fs::path(a.out) / "pareto.svg",
                        ParetoSvg(ReadParetoPoints(csv), a.min_detection,
                                  "Run time against error: " + fs::path(a.scene).filename().string()));
    return;
  }
  const SceneFile scene = LoadSceneFile(a.scene);
  std::vector<int> spps = ParseInts(a.spp.empty() ? (a.quick ? "1,4" : "1,4,16,64") : a.spp, "--spp");
  std::vector<ExtractionMethod> methods;
  {
    // Several laser sheets: com and max find one stripe per search line, so
    // they are left out of the default list (as scan takes multicom).
    int sheets = 0;
    for (const LaserProjector& l : scene.sensor.lasers) sheets += l.sheet_count();
    const char* defaults = sheets > 1 ? "multicom,steger" : a.quick ? "com,steger" : "com,multicom,steger,max";
    std::stringstream ss(a.methods.empty() ? defaults : a.methods);
    for (std::string m; std::getline(ss, m, ',');) methods.push_back(ParseMethod(m, "--methods"));
    if (methods.empty()) throw InputError("--methods", "no method given");
  }
  if (a.threads < 0) throw InputError("--threads", "must be >= 0");
  const fs::path out = a.out;
  fs::create_directories(out / "runs");
  std::vector<Row> rows;
  const std::vector<RenderConfig> ladder = Ladder(scene, spps, methods, a.quick);
  for (const RenderConfig& c : ladder) {
    Row render_row;
    render_row.config = c;
    const fs::path dir = out / "runs" / c.name;
    RenderRun(scene, c, a.threads, dir, &render_row);
    for (ExtractionMethod m : c.methods) {
      Row row = render_row;
      row.method = m;
      ScanAndEvaluate(dir, m, a.threads, &row);
      rows.push_back(row);
      if (!a.quiet) {
        std::cerr << c.name << " " << MethodName(m) << ": render " << Num(row.render_cpu_ms, 0) << " ms CPU ("
                  << Num(row.render_wall_ms, 0) << " wall), scan " << Num(row.scan_cpu_ms, 1) << " ms CPU; centre rms "
                  << StatText(row.eval.center_px, &ErrorStats::rms, 4) << " px, point rms "
                  << StatText(row.eval.point_mm, &ErrorStats::rms, 4) << " mm\n";
      }
    }
    WriteFileAtomically(out / "sweep.csv", Csv(rows));  // after every configuration: partial results survive
  }
  WriteFileAtomically(out / "pareto.svg",
                      ParetoSvg(ParetoPoints(rows), a.min_detection, "Run time against error: " + scene.path.filename().string()));
  if (!a.quiet) std::cerr << "wrote " << (out / "sweep.csv").string() << " and " << (out / "pareto.svg").string() << "\n";
}

void Add(CLI::App& app) {
  auto args = std::make_shared<SweepArgs>();
  auto* cmd = app.add_subcommand(
      "sweep", "Render, scan and evaluate a scene over a ladder of settings: run time against error (sweep.csv, pareto.svg)");
  cmd->add_option("SCENE", args->scene, "Scene file (JSON)")->required();
  cmd->add_option("--out", args->out, "Output folder (runs/<configuration>/, sweep.csv, pareto.svg)")->required();
  cmd->add_option("--spp", args->spp, "Samples per pixel ladder (default 1,4,16,64; --quick: 1,4)");
  cmd->add_option("--methods", args->methods,
                  "Extraction methods for the spp ladder (default com,multicom,steger,max; --quick: com,steger; "
                  "several laser sheets: multicom,steger)");
  cmd->add_option("--threads", args->threads, "Threads for rendering and extraction (0: all)")->capture_default_str();
  cmd->add_option("--min-detection", args->min_detection,
                  "The Pareto front only takes configurations that detect at least this fraction of the true centres")
      ->capture_default_str();
  cmd->add_flag("--replot", args->replot, "Only redraw DIR/pareto.svg from DIR/sweep.csv");
  cmd->add_flag("--quick", args->quick, "A short ladder (spp 1,4; bounces 0; com and steger)");
  cmd->add_flag("--quiet", args->quiet, "No progress on stderr");
  cmd->callback([args] { Run(*args); });
}

}  // namespace

LT_REGISTER_COMMAND("sweep", Add);

}  // namespace lt::cli
