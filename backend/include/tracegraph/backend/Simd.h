/// @file Simd.h
/// Which SIMD instruction set the packet kernels use, chosen at run time from the CPU.
///
/// The library is compiled for the x86-64 baseline (SSE2); the AVX2 and AVX-512 kernels live in
/// translation units of their own, compiled for those instruction sets and entered only after
/// the CPU (and the operating system's register saving) has been checked. Every kernel computes
/// bit-identical results: they differ in how many box tests one instruction performs, never in
/// the arithmetic.
#pragma once

#include <optional>
#include <string_view>
#include <vector>

namespace tg {

/// Instruction sets of the packet kernels, slowest first.
enum class SimdIsa : unsigned char {
  Portable,  ///< plain C++ (SSE2 on x86-64, where it is the baseline)
  Avx2,      ///< 8 lanes per instruction (AVX2 + FMA CPUs)
  Avx512,    ///< 16 lanes per instruction (AVX-512F CPUs)
};

/// "portable", "avx2" or "avx512".
std::string_view simdIsaName(SimdIsa isa);

/// Parses a name written by simdIsaName.
std::optional<SimdIsa> parseSimdIsa(std::string_view name);

/// Instruction sets this build contains and this CPU runs, slowest first.
std::vector<SimdIsa> supportedSimdIsas();

/// The instruction set the packet kernels use now: the widest supported one (AVX2 rather than
/// AVX-512 on CPUs that run 512-bit operations as two 256-bit halves, AMD's family 19h, where
/// the AVX2 kernels are faster), unless the environment variable TG_SIMD names another
/// supported one, or setSimdIsa chose one.
SimdIsa activeSimdIsa();

/// Makes the packet kernels use `isa` (for tests and benchmarks that compare kernels). Returns
/// false, changing nothing, when `isa` is not supported here. Must not overlap ray queries.
bool setSimdIsa(SimdIsa isa);

}  // namespace tg
