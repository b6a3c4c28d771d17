// Draws a finished run's plots (OUT/plot_*.png) by running tools/plots/plot_run.py on its output
// folder with Debian's python3-matplotlib, after the run, so that plotting never slows a run down.
#pragma once

#include <string>

namespace sear {

// Runs `PYTHON SCRIPT out_dir`: PYTHON is $SEAR_PYTHON, else /usr/bin/python3 (not a pyenv shim
// that PATH may put first); SCRIPT is $SEAR_PLOT_SCRIPT, else the one this build was configured
// with. What the plotter prints goes to out_dir/plots.log. Returns true when the plots were
// written; otherwise prints one warning line on standard error, and the run's outcome is
// unchanged.
bool write_plots(const std::string& out_dir);

}  // namespace sear
