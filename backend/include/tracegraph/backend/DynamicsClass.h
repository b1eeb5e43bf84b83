/// @file DynamicsClass.h
/// The three dynamics classes of the paper (Wald, Benthin, Slusallek 2003, section 3).
#pragma once

#include <cstdint>

namespace tg {

/// How the backend holds a piece of geometry (architecture, "The three dynamics classes").
enum class DynamicsClass : std::uint8_t {
  Static,     ///< never moves: merged into world-space objects built with the SAH builder
  Rigid,      ///< moves as a whole: an object held by instances whose matrices change
  Deforming,  ///< its points change: its own object, rebuilt with the fast builder
};

}  // namespace tg
