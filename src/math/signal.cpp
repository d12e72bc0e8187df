// Signal: a value that is a constant or a table in time, interpolated linearly.
#include <linx/signal.hpp>

#include <algorithm>

namespace linx {

namespace {
// The segment [times[i], times[i + 1]) that t falls in: i in [0, n - 2], or -1 before the first
// time, n - 1 from the last on.
std::ptrdiff_t segment(const std::vector<double>& times, double t) {
  const auto after = std::upper_bound(times.begin(), times.end(), t);
  return (after - times.begin()) - 1;
}
}  // namespace

double Signal::at(double t) const {
  if (times.size() < 2) return values.empty() ? 0.0 : values.front();
  const std::ptrdiff_t i = segment(times, t);
  if (i < 0) return values.front();
  if (i >= static_cast<std::ptrdiff_t>(times.size()) - 1) return values.back();
  const auto k = static_cast<std::size_t>(i);
  const double s = (t - times[k]) / (times[k + 1] - times[k]);
  return values[k] + s * (values[k + 1] - values[k]);
}

double Signal::rate(double t) const {
  if (times.size() < 2) return 0.0;
  const std::ptrdiff_t i = segment(times, t);
  if (i < 0 || i >= static_cast<std::ptrdiff_t>(times.size()) - 1) return 0.0;
  const auto k = static_cast<std::size_t>(i);
  return (values[k + 1] - values[k]) / (times[k + 1] - times[k]);
}

bool VectorSignal::isZero() const {
  return std::all_of(components.begin(), components.end(), [](const Signal& s) {
    return std::all_of(s.values.begin(), s.values.end(), [](double v) { return v == 0.0; });
  });
}

}  // namespace linx
