// Run-time choice of the packet kernel's instruction set.
#include "tracegraph/backend/Simd.h"

#include <atomic>
#include <cstdlib>

#include "PacketKernel.h"

namespace tg {
namespace {

constexpr std::string_view kIsaNames[] = {"portable", "avx2", "avx512"};

/// True when this CPU (and operating system) runs the kernel of `isa` and the build has it.
bool cpuRuns(SimdIsa isa) {
  switch (isa) {
    case SimdIsa::Portable:
      return true;
    case SimdIsa::Avx2:
#if defined(__x86_64__) || defined(__i386__)
      // __builtin_cpu_supports also checks that the OS saves the wide registers (XGETBV).
      return detail::packetKernelsAvx2().traverse != nullptr && __builtin_cpu_supports("avx2") &&
             __builtin_cpu_supports("fma");
#else
      return false;
#endif
    case SimdIsa::Avx512:
#if defined(__x86_64__) || defined(__i386__)
      return detail::packetKernelsAvx512().traverse != nullptr && __builtin_cpu_supports("avx512f");
#else
      return false;
#endif
  }
  return false;
}

detail::PacketKernels kernelsOf(SimdIsa isa) {
  switch (isa) {
    case SimdIsa::Avx2:
      return detail::packetKernelsAvx2();
    case SimdIsa::Avx512:
      return detail::packetKernelsAvx512();
    case SimdIsa::Portable:
      break;
  }
  return detail::packetKernelsPortable();
}

SimdIsa initialIsa() {
  if (const char* requested = std::getenv("TG_SIMD")) {
    const std::optional<SimdIsa> isa = parseSimdIsa(requested);
    if (isa && cpuRuns(*isa)) return *isa;
  }
  const std::vector<SimdIsa> isas = supportedSimdIsas();
  return isas.back();
}

/// The active choice, one slot per instruction set so that a switch never tears a pair of
/// kernels apart; set on first use and by setSimdIsa.
struct ActiveKernels {
  detail::PacketKernels byIsa[3] = {kernelsOf(SimdIsa::Portable), kernelsOf(SimdIsa::Avx2),
                                    kernelsOf(SimdIsa::Avx512)};
  std::atomic<SimdIsa> isa{initialIsa()};
};

ActiveKernels& active() {
  static ActiveKernels instance;
  return instance;
}

}  // namespace

std::string_view simdIsaName(SimdIsa isa) {
  const auto i = static_cast<std::size_t>(isa);
  return i < std::size(kIsaNames) ? kIsaNames[i] : "unknown";
}

std::optional<SimdIsa> parseSimdIsa(std::string_view name) {
  for (std::size_t i = 0; i < std::size(kIsaNames); ++i)
    if (kIsaNames[i] == name) return static_cast<SimdIsa>(i);
  return std::nullopt;
}

std::vector<SimdIsa> supportedSimdIsas() {
  std::vector<SimdIsa> isas;
  for (SimdIsa isa : {SimdIsa::Portable, SimdIsa::Avx2, SimdIsa::Avx512})
    if (cpuRuns(isa)) isas.push_back(isa);
  return isas;
}

SimdIsa activeSimdIsa() {
  return active().isa.load(std::memory_order_relaxed);
}

bool setSimdIsa(SimdIsa isa) {
  if (!cpuRuns(isa)) return false;
  active().isa.store(isa, std::memory_order_relaxed);
  return true;
}

namespace detail {
const PacketKernels& activePacketKernels() {
  ActiveKernels& a = active();
  return a.byIsa[static_cast<std::size_t>(a.isa.load(std::memory_order_relaxed))];
}
}  // namespace detail

}  // namespace tg
