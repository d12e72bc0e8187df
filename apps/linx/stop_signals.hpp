// How every `linx` command stops on SIGINT and SIGTERM (docs/reliability.md): one handler that only
// notes the signal, polled by the commands where stopping leaves their output whole, and a watchdog
// for the places that cannot poll: a long simulation step, and the reading of the inputs.
#pragma once

#include <chrono>
#include <condition_variable>
#include <csignal>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

namespace linx::cli {

/// While one lives, SIGINT and SIGTERM set a flag (received()) and nothing else. The handler is
/// installed without SA_RESTART, so that a sleep or a wait ends at once. SIGXFSZ is ignored, so
/// that passing the file size limit (ulimit -f) is a write error naming the file rather than a
/// silent death. The previous dispositions come back when the last one goes.
class StopSignals {
 public:
  StopSignals();
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  /// The stop signal received since the first StopSignals was made, or 0.
  static int received();
};

/// Ends the process when a stop signal finds it inside a long computation: if the work marked
/// busy has not come back `grace` after a stop signal, `on_timeout` runs on the watchdog's thread
/// while the work is held (leave() waits), and must end the process (std::_Exit).
class StopWatchdog {
 public:
  StopWatchdog(std::chrono::milliseconds grace, std::function<void()> on_timeout);
  ~StopWatchdog();
  StopWatchdog(const StopWatchdog&) = delete;
  StopWatchdog& operator=(const StopWatchdog&) = delete;

  /// Marks the work busy while it lives.
  class Busy {
   public:
    explicit Busy(StopWatchdog& dog) : dog_(dog) { dog_.setBusy(true); }
    ~Busy() { dog_.setBusy(false); }
    Busy(const Busy&) = delete;
    Busy& operator=(const Busy&) = delete;

   private:
    StopWatchdog& dog_;
  };

 private:
  void setBusy(bool busy);
  void watch();

  std::chrono::milliseconds grace_;
  std::function<void()> on_timeout_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool busy_ = false, done_ = false;
  std::thread thread_;
};

/// Runs `load` (reading a scene or a model with its meshes and includes, building its world:
/// nothing written yet) so that a stop signal ends it within 50 ms, however long a parse or a
/// triangulation runs without looking: the process ends with exit status 130 and
/// `linx: SOURCE: interrupted while reading it; nothing written`. A signal that arrives as the
/// loading ends does the same once it has.
void whileLoading(const std::string& source, const std::function<void()>& load);

}  // namespace linx::cli
