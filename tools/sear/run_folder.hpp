// Where a run writes: one folder per run, never shared with another run's files. By default
// sear-out/SCENARIO/ (`sear view`: sear-out/SCENARIO.view/), with sear-out/latest naming the last.
#pragma once

#include <string>

namespace sear {

inline constexpr const char* kOutputRoot = "sear-out";
// Left in every run folder: a folder holding it is a run's, which the next run may empty.
inline constexpr const char* kRunFolderMark = ".sear-run";

// sear-out/NAME for a scenario (or project) called `name`, its characters made safe for a folder
// name; `view`: sear-out/NAME.view, so that a viewed run never replaces a headless one.
std::string default_run_folder(const std::string& name, bool view);

// Makes `dir` ready for a run: creates it, or empties it when it holds an earlier run (its
// mark, or an unmarked one's world.json and summary.json), then marks it. A folder holding anything else is refused (std::runtime_error naming it
// and a file in it), so a run never mixes its files with others nor deletes what is not a run's.
void prepare_run_folder(const std::string& dir);

// sear-out/latest -> `dir`'s name, replaced at once; `dir` is one of sear-out's folders. A
// failure costs a warning, never the run.
void point_latest_at(const std::string& dir);

}  // namespace sear
