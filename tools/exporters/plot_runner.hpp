// Draws a finished run's plots (OUT/plot_*.png) by running tools/plots/plot_run.py on its output
// folder with Debian's python3-matplotlib, after the run, so that plotting never slows a run down.
// `sear run` draws them in the background: matplotlib takes seconds of CPU for a run's plots, more
// than a minute-long run steps for, so the run exits once its summary is written and the plotter
// goes on alone, holding a lock on the output folder until its last plot is in place.
#pragma once

#include <string>

namespace sear {

// Runs `PYTHON SCRIPT out_dir` and waits for it: PYTHON is $SEAR_PYTHON, else /usr/bin/python3
// (not a pyenv shim that PATH may put first); SCRIPT is $SEAR_PLOT_SCRIPT, else the one this build
// was configured with. What the plotter prints goes to out_dir/plots.log. Returns true when the
// plots were written; otherwise prints one warning line on standard error, and the run's outcome
// is unchanged.
bool write_plots(const std::string& out_dir);

// A run's claim on its output folder for plotting: an flock(2) on the folder itself (no file is
// added to it), which the background plotter inherits and keeps until its plots are all written,
// so that `flock OUT true` waits for them.
class PlotFolder {
 public:
  explicit PlotFolder(std::string out_dir) : out_dir_(std::move(out_dir)) {}
  ~PlotFolder();
  PlotFolder(const PlotFolder&) = delete;
  PlotFolder& operator=(const PlotFolder&) = delete;

  // Before the run writes its files: waits while the plotter of an earlier run into the folder
  // still reads the files this run is about to rewrite (saying so unless `quiet`), then removes
  // that run's plots, so that none is taken for this run's. A stop signal ends the wait.
  void claim(bool quiet);
  // Starts the plotter without waiting for it; it holds the claim from here on. False, with one
  // warning line, if it could not be started; a plotter that fails later says why in plots.log.
  bool draw_in_background();
  // Waits until the plotter drawing into `out_dir` (if any) is done: `sear run --wait-plots`.
  static void wait_for_plotter(const std::string& out_dir);

 private:
  std::string out_dir_;
  int lock_fd_ = -1;
};

}  // namespace sear
