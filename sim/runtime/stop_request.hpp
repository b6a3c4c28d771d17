// Ctrl-C, SIGTERM and SIGHUP end a run early but cleanly: the handler only records the request,
// and every loop of the run that can wait (firmware hand-offs, compiler output, physics steps)
// polls it, so the run stops within a fraction of a second with its files complete.
#pragma once

namespace sear {

// Installs the handlers without SA_RESTART, so that a blocking read or wait returns at once.
// Also ignores SIGPIPE (a closed stdout is handled where it is written) and SIGXFSZ (a file at
// its size limit fails its write instead of killing the process).
void install_stop_signals();
bool stop_requested();
// The first signal that asked to stop, or 0.
int stop_signal();

}  // namespace sear
