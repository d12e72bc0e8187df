// Stand-ins for the peers whose Debian packages were not found at configure time: each returns no
// variants, so the table lists linx alone for that engine. Compiled only for missing peers.
#include "../engine.hpp"
#include "../model_engine.hpp"

namespace bench {

#ifndef LINX_BENCH_HAVE_ODE
std::vector<Variant> odeVariants(const Scene&) {
  return {};
}
std::vector<Variant> odeSweep(const Scene&, const std::vector<int>&) {
  return {};
}
std::vector<Variant> odeIntegrators(const Scene&) {
  return {};
}
#endif
#ifndef LINX_BENCH_HAVE_BULLET
std::vector<Variant> bulletVariants(const Scene&) {
  return {};
}
std::vector<Variant> bulletSweep(const Scene&, const std::vector<int>&) {
  return {};
}
#endif
#ifndef LINX_BENCH_HAVE_MUJOCO
std::vector<Variant> mujocoVariants(const Scene&) {
  return {};
}
std::vector<Variant> mujocoSweep(const Scene&, const std::vector<int>&) {
  return {};
}
std::vector<Variant> mujocoIntegrators(const Scene&) {
  return {};
}
std::vector<ModelVariant> mujocoModelVariants() {
  return {};
}
#endif
#ifndef LINX_BENCH_HAVE_SIMBODY
std::vector<Variant> simbodyIntegrators(const Scene&) {
  return {};
}
#endif
#ifndef LINX_BENCH_HAVE_DART
std::vector<Variant> dartVariants(const Scene&) {
  return {};
}
std::vector<Variant> dartSweep(const Scene&, const std::vector<int>&) {
  return {};
}
#endif

}  // namespace bench
