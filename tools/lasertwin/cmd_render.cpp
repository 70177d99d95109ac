// `lasertwin render SCENE --out DIR [--frames A:B] [--spp N] [--threads N]
// [--seed N] [--resume] [--quiet]`: renders a scene's frames with ground truth
// into a run folder (render/run_folder.h, docs/run-folder.md).
#include <iostream>
#include <memory>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/frame_range.h"
#include "render/frame_renderer.h"
#include "render/frame_writer.h"
#include "render/progress.h"
#include "render/run_folder.h"
#include "scene/embree_scene.h"
#include "scene/scene_file.h"
#include "tools/lasertwin/command.h"

namespace lt::cli {
namespace {

struct RenderArgs {
  std::string scene;
  std::string out;
  std::string frames = ":";
  int spp = 0;
  int threads = -1;
  int64_t seed = -1;
  bool resume = false;
  bool quiet = false;
};

void Run(const RenderArgs& a) {
  SceneFile scene = LoadSceneFile(a.scene);
  RenderOverrides overrides;
  if (a.spp > 0) overrides.spp = a.spp;
  if (a.threads >= 0) overrides.threads = a.threads;
  if (a.seed >= 0) overrides.seed = uint64_t(a.seed);
  const FrameRange range = FrameRange::Parse(a.frames);
  auto [begin, end] = range.Resolve(scene.render.frames);
  if (!a.quiet) {
    if (range.Exceeds(scene.render.frames)) {
      std::cerr << "lasertwin: note: --frames " << a.frames << ": the scene has " << scene.render.frames
                << " frames; rendering " << begin << ".." << end - 1 << "\n";
    }
    for (const std::string& note : MotionNotes(scene.motion)) std::cerr << "motion: " << note << "\n";
  }

  // The resolved scene with the overrides applied, so the run folder says what was rendered.
  nlohmann::json resolved = scene.resolved;
  if (overrides.spp) resolved["render"]["spp"] = *overrides.spp;
  if (overrides.seed) resolved["seed"] = *overrides.seed;
  // Everything that can refuse the scene runs before the run folder is made, so a
  // refused scene leaves no folder behind that a later render would take for a run.
  auto geometry = std::make_shared<SceneGeometry>(LoadSceneGeometry(scene));
  EmbreeScene embree(geometry);
  FrameRenderer renderer(scene, embree, overrides);
  RunFolder run(a.out, resolved, a.resume);
  WriteFileAtomically(run.dir() / "rig.json", SensorRigToJson(scene.sensor).dump(2) + "\n");
  Progress progress(end - begin, a.quiet);
  int rendered = 0;
  double total_ms = 0;
  for (int i = begin; i < end; ++i) {
    if (run.IsComplete(i)) {
      progress.Step("frame");
      continue;
    }
    RenderedFrame frame = renderer.Render(i);
    run.CompleteFrame(i, WriteFrame(run, frame, i, scene, renderer.seed(), renderer.spp()));
    total_ms += frame.stats.render_ms + frame.stats.ground_truth_ms;
    ++rendered;
    progress.Step("frame");
  }
  if (!a.quiet) {
    std::cerr << "rendered " << rendered << " frame" << (rendered == 1 ? "" : "s");
    if (rendered > 0) std::cerr << " (" << total_ms / rendered << " ms per frame)";
    if (rendered < end - begin) std::cerr << ", " << (end - begin - rendered) << " already complete";
    std::cerr << " into " << run.dir().string() << "\n";
  }
}

void Add(CLI::App& app) {
  auto args = std::make_shared<RenderArgs>();
  CLI::App* cmd = app.add_subcommand("render", "Render a scene's frames with ground truth into a run folder");
  cmd->add_option("SCENE", args->scene, "Scene file (JSON)")->required();
  cmd->add_option("--out", args->out, "Run folder to write")->required();
  cmd->add_option("--frames", args->frames, "Frames to render: A:B (A inclusive, B exclusive), A:, :B or N");
  cmd->add_option("--spp", args->spp, "Samples per pixel (overrides render.spp)")->check(CLI::Range(1, 65536));
  cmd->add_option("--threads", args->threads, "Threads (0 = all; overrides render.threads)")
      ->check(CLI::Range(0, 1024));
  cmd->add_option("--seed", args->seed, "Random seed (overrides the scene's seed)")->check(CLI::NonNegativeNumber);
  cmd->add_flag("--resume", args->resume, "Continue an interrupted run in the same folder");
  cmd->add_flag("--quiet", args->quiet, "No progress or summary on stderr");
  cmd->callback([args] { Run(*args); });
}

LT_REGISTER_COMMAND("render", Add);

}  // namespace
}  // namespace lt::cli
