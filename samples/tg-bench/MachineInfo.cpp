#include "MachineInfo.h"

#include <fstream>
#include <thread>

#include "tracegraph/backend/Simd.h"

namespace tg::bench {

int hardwareThreads() {
  const unsigned n = std::thread::hardware_concurrency();
  return n == 0 ? 1 : static_cast<int>(n);
}

std::string machineDescription() {
  std::string model = "unknown CPU";
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line;
  while (std::getline(cpuinfo, line)) {
    if (line.rfind("model name", 0) != 0) continue;
    const std::size_t colon = line.find(':');
    if (colon == std::string::npos) continue;
    const std::size_t begin = line.find_first_not_of(" \t", colon + 1);
    if (begin != std::string::npos) model = line.substr(begin);
    break;
  }
  // The packet kernel in use says which SIMD width the packet rows measured.
  return model + ", " + std::to_string(hardwareThreads()) + " cores, SIMD " +
         std::string(simdIsaName(activeSimdIsa()));
}

}  // namespace tg::bench
