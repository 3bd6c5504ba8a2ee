// ultrafusion: recorded multi-sensor data -> trajectory, map, splats. Each subcommand lives in its own file
// and registers itself here. Exit codes: 0 ok, 1 runtime or data error, 2 usage error.
#include <CLI/CLI.hpp>
#include <iostream>

#include "odometry/types/process_memory.h"
#include "viewer/app/cli/calibrate_command.h"
#include "viewer/app/cli/colorize_command.h"
#include "viewer/app/cli/eval_command.h"
#include "viewer/app/cli/exit_codes.h"
#include "viewer/app/cli/export_command.h"
#include "viewer/app/cli/info_command.h"
#include "viewer/app/cli/render_command.h"
#include "viewer/app/cli/run_command.h"
#include "viewer/app/cli/sim_command.h"
#include "viewer/app/cli/splat_command.h"
#include "viewer/app/cli/track_command.h"

int main(int argc, char** argv) {
  uf::KeepFreedMemoryForReuse();
  CLI::App app{"ultrafusion: multi-sensor odometry, mapping and Gaussian splatting"};
  app.set_version_flag("--version", std::string("ultrafusion ") + UF_VERSION);
  app.require_subcommand(1);

  auto calibrate = uf::app::AddCalibrateCommand(app);
  auto colorize = uf::app::AddColorizeCommand(app);
  auto eval = uf::app::AddEvalCommand(app);
  auto exporter = uf::app::AddExportCommand(app);
  auto info = uf::app::AddInfoCommand(app);
  auto render = uf::app::AddRenderCommand(app);
  auto run = uf::app::AddRunCommand(app);
  auto sim = uf::app::AddSimCommand(app);
  auto splat = uf::app::AddSplatCommand(app);
  auto track = uf::app::AddTrackCommand(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints help, version or the usage error
    return code == 0 ? uf::app::kExitOk : uf::app::kExitUsage;
  }
  if (app.got_subcommand(calibrate.command)) return calibrate.run();
  if (app.got_subcommand(colorize.command)) return colorize.run();
  if (app.got_subcommand(eval.command)) return eval.run();
  if (app.got_subcommand(exporter.command)) return exporter.run();
  if (app.got_subcommand(info.command)) return info.run();
  if (app.got_subcommand(render.command)) return render.run();
  if (app.got_subcommand(run.command)) return run.run();
  if (app.got_subcommand(sim.command)) return sim.run();
  if (app.got_subcommand(splat.command)) return splat.run();
  if (app.got_subcommand(track.command)) return track.run();
  return uf::app::kExitUsage;
}
