// Run-time choice of the packet kernel's instruction set.
#include "tracegraph/backend/Simd.h"

#include <atomic>
#include <cstdlib>

#if defined(__x86_64__) || defined(__i386__)
#include <cpuid.h>
#endif

#include "PacketKernel.h"

namespace tg {
namespace {

constexpr std::string_view kIsaNames[] = {"portable", "avx2", "avx512"};

/// True when this CPU (and operating system) executes the instructions of `isa`.
/// __builtin_cpu_supports also checks that the OS saves the wide registers (XGETBV).
bool cpuHas(SimdIsa isa) {
  switch (isa) {
    case SimdIsa::Portable:
      return true;
    case SimdIsa::Avx2:
#if defined(__x86_64__) || defined(__i386__)
      return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
      return false;
#endif
    case SimdIsa::Avx512:
#if defined(__x86_64__) || defined(__i386__)
      return __builtin_cpu_supports("avx512f");
#else
      return false;
#endif
  }
  return false;
}

/// The kernels of `isa`, or none (null members) when this CPU lacks its instructions. The CPU
/// is asked first: the functions that hand out a wider set's kernels are compiled for that set
/// too, and GCC builds their result with its vector moves (512-bit ones for AVX-512), which an
/// AVX2-only CPU stops at as illegal instructions.
detail::PacketKernels kernelsOf(SimdIsa isa) {
  if (!cpuHas(isa)) return {};
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

/// True when this CPU runs the kernels of `isa` and the build has them.
bool cpuRuns(SimdIsa isa) {
  return isa == SimdIsa::Portable || kernelsOf(isa).traverse != nullptr;
}

/// True on CPUs that execute a 512-bit operation as two 256-bit halves: AMD's family 19h, whose
/// Zen 4 models are the first AMD cores with AVX-512 (its Zen 3 models have none). There the
/// AVX-512 node test gains nothing from testing two boxes per instruction and pays for building
/// the slot pairs. One thread, 640x480, alternating processes on an AMD EPYC of that family:
/// primary packets from the BART cameras, kitchen 22.8-23.2 ms with the AVX-512 kernels against
/// 21.0-21.2 with the AVX2 ones, robots 23.7-23.8 against 21.9-22.0; from outside the scenes
/// 8-13% less time; kitchen frames at two threads, `opengl` 41.3-41.9 -> 43.8-44.0 fps and
/// `whitted` 5.04-5.12 -> 5.35-5.39. Shadow packets the same either way.
/// Family 1Ah (Zen 5) runs 512-bit operations at full width and keeps the AVX-512 kernels: on an
/// AMD EPYC of that family the two sets came within noise of each other from the BART cameras
/// and in `opengl` frames, and from outside the scenes each won on some (kitchen and robots
/// 7-9% faster with AVX2, the museum 5-9% with AVX-512).
bool splitsWideVectors() {
#if (defined(__x86_64__) || defined(__i386__)) && defined(__GNUC__)
  unsigned eax = 0, ebx = 0, ecx = 0, edx = 0;
  if (__get_cpuid(0, &eax, &ebx, &ecx, &edx) == 0) return false;
  // "AuthenticAMD" in EBX, EDX, ECX.
  const bool amd = ebx == 0x68747541u && edx == 0x69746e65u && ecx == 0x444d4163u;
  if (!amd || __get_cpuid(1, &eax, &ebx, &ecx, &edx) == 0) return false;
  const unsigned baseFamily = (eax >> 8) & 0xFu;
  const unsigned family = baseFamily == 0xFu ? baseFamily + ((eax >> 20) & 0xFFu) : baseFamily;
  return family == 0x19u;
#else
  return false;
#endif
}

SimdIsa initialIsa() {
  if (const char* requested = std::getenv("TG_SIMD")) {
    const std::optional<SimdIsa> isa = parseSimdIsa(requested);
    if (isa && cpuRuns(*isa)) return *isa;
  }
  const std::vector<SimdIsa> isas = supportedSimdIsas();
  if (isas.back() == SimdIsa::Avx512 && splitsWideVectors()) return SimdIsa::Avx2;
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
