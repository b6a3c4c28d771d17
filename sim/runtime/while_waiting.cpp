#include "runtime/while_waiting.hpp"

#include <utility>

namespace sear {
namespace {

// The run steps on one thread, and only it waits; no lock is needed.
std::function<void()> g_work;

}  // namespace

WhileWaiting::WhileWaiting(std::function<void()> work) { g_work = std::move(work); }

WhileWaiting::~WhileWaiting() { g_work = nullptr; }

void while_waiting() {
  if (g_work) g_work();
}

}  // namespace sear
