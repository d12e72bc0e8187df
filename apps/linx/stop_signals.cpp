#include "stop_signals.hpp"

#include "cli_common.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>

namespace linx::cli {

namespace {

volatile std::sig_atomic_t g_received = 0;
int g_depth = 0;  // StopSignals alive (the main thread makes them)
struct sigaction g_old_int {
}, g_old_term{}, g_old_xfsz{};

extern "C" void onStopSignal(int signal) {
  g_received = signal;
}

}  // namespace

StopSignals::StopSignals() {
  if (g_depth++ > 0) return;
  g_received = 0;
  struct sigaction action {};
  action.sa_handler = onStopSignal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = 0;  // no SA_RESTART
  sigaction(SIGINT, &action, &g_old_int);
  sigaction(SIGTERM, &action, &g_old_term);
  struct sigaction ignore {};
  ignore.sa_handler = SIG_IGN;
  sigemptyset(&ignore.sa_mask);
  sigaction(SIGXFSZ, &ignore, &g_old_xfsz);
}

StopSignals::~StopSignals() {
  if (--g_depth > 0) return;
  sigaction(SIGINT, &g_old_int, nullptr);
  sigaction(SIGTERM, &g_old_term, nullptr);
  sigaction(SIGXFSZ, &g_old_xfsz, nullptr);
}

int StopSignals::received() {
  return g_received;
}

StopWatchdog::StopWatchdog(std::chrono::milliseconds grace, std::function<void()> on_timeout)
    : grace_(grace), on_timeout_(std::move(on_timeout)), thread_([this] { watch(); }) {}

StopWatchdog::~StopWatchdog() {
  {
    std::lock_guard lock(mutex_);
    done_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void StopWatchdog::setBusy(bool busy) {
  std::lock_guard lock(mutex_);
  busy_ = busy;
}

// Polls for a signal every 50 ms (a handler cannot wake a condition variable), then gives the
// busy work its grace.
void StopWatchdog::watch() {
  constexpr auto kTick = std::chrono::milliseconds(50);
  std::unique_lock lock(mutex_);
  while (!done_) {
    if (StopSignals::received() == 0) {
      wake_.wait_for(lock, kTick);
      continue;
    }
    const auto deadline = std::chrono::steady_clock::now() + grace_;
    while (!done_ && std::chrono::steady_clock::now() < deadline)
      wake_.wait_until(lock, std::min(deadline, std::chrono::steady_clock::now() + kTick));
    if (!done_ && busy_) on_timeout_();  // holding the lock: the work cannot come back meanwhile
    // Not busy at the deadline: the work is polling the signal itself.
    while (!done_) wake_.wait(lock);
  }
}

namespace {

[[noreturn]] void interruptedWhileLoading(const std::string& source) {
  say(stderr, "linx: {}: interrupted while reading it; nothing written\n", source);
  std::_Exit(kExitInterrupted);
}

}  // namespace

void whileLoading(const std::string& source, const std::function<void()>& load) {
  const StopSignals signals;
  {
    // No grace: nothing is written while loading, so there is nothing to wait for.
    StopWatchdog watchdog(std::chrono::milliseconds(0),
                          [&source] { interruptedWhileLoading(source); });
    const StopWatchdog::Busy busy(watchdog);
    load();
  }
  if (StopSignals::received() != 0) interruptedWhileLoading(source);
}

}  // namespace linx::cli
