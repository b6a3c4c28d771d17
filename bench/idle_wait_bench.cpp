// The idle-loop check's speed: `sear run` on a rover whose firmware waits for each tick of a 1 kHz
// timer in `while (!flag) {}` (bench/firmware/tick_wait.c), against the same world with a firmware
// that only calls delay_ms(1) (what physics and the hand-off allow). Prints the wall-clock
// real-time factor (simulated seconds per wall second, summary.json's real_time_factor), median of
// 3 runs, on the host as it is and beside one busy-spinning process.
// Usage: idle_wait_bench [seconds simulated per run, default 5]
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace {

std::string project(const char* firmware, double duration_s) {
  std::ostringstream p;
  p << "<project name=\"bench\">\n  <run duration=\"" << duration_s << "\" seed=\"1\" trace_rate=\"10\"/>\n"
    << "  <world step=\"0.001\">\n    <terrain type=\"flat\"/>\n  </world>\n"
    << "  <robot file=\"" << SEAR_ASSET_DIR << "/robots/rover.xml\">\n    <pose x=\"0\" y=\"0\"/>\n"
    << "    <mcu name=\"main\">\n      <firmware executable=\"" << firmware << "\"/>\n    </mcu>\n"
    << "  </robot>\n</project>\n";
  return p.str();
}

double one_run(const std::filesystem::path& dir, const char* firmware, double duration_s) {
  std::ofstream(dir / "project.xml") << project(firmware, duration_s);
  const std::string cmd = std::string(SEAR_BINARY) + " run " + (dir / "project.xml").string() + " -o " +
                          (dir / "out").string() + " >/dev/null 2>&1";
  if (std::system(cmd.c_str()) != 0) return -1;
  std::ifstream in(dir / "out" / "summary.json");
  std::stringstream s;
  s << in.rdbuf();
  std::smatch m;
  const std::string text = s.str();
  if (!std::regex_search(text, m, std::regex("\"real_time_factor\"\\s*:\\s*([0-9.eE+-]+)"))) return -1;
  return std::stod(m[1]);
}

double median_of_3(const std::filesystem::path& dir, const char* firmware, double duration_s) {
  std::vector<double> rtf;
  for (int i = 0; i < 3; ++i) rtf.push_back(one_run(dir, firmware, duration_s));
  std::sort(rtf.begin(), rtf.end());
  return rtf[1];
}

double load_average() {
  double l = 0;
  if (FILE* f = std::fopen("/proc/loadavg", "r")) {
    if (std::fscanf(f, "%lf", &l) != 1) l = 0;
    std::fclose(f);
  }
  return l;
}

}  // namespace

int main(int argc, char** argv) {
  const double duration_s = argc > 1 ? std::atof(argv[1]) : 5.0;
  const auto dir = std::filesystem::temp_directory_path() / ("idle_wait_bench." + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  for (const bool busy : {false, true}) {
    pid_t spinner = -1;
    if (busy) {
      spinner = fork();
      if (spinner == 0)
        for (volatile unsigned long spin = 0;; spin = spin + 1) {
        }
    }
    const double load = load_average();
    const double wait = median_of_3(dir, BENCH_TICK_WAIT_FIRMWARE, duration_s);
    const double delay = median_of_3(dir, BENCH_IDLE_FIRMWARE, duration_s);
    std::printf("%-22s load %.2f  1 kHz while(!flag) wait: %6.2fx   delay_ms(1) loop: %6.2fx real time\n",
                busy ? "one busy process:" : "host as it is:", load, wait, delay);
    std::fflush(stdout);
    if (spinner > 0) {
      kill(spinner, SIGKILL);
      waitpid(spinner, nullptr, 0);
    }
  }
  std::filesystem::remove_all(dir);
  return 0;
}
