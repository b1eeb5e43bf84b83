/// @file AffParser.h
/// Reads AFF (BART) and plain NFF files into an AffDocument.
///
/// Accepted: every AFF command of docs/aff-format.md and Haines' NFF (`v b l f s p pp c`),
/// including the Assimp habit of a texture name after the eight `f` numbers on the same line.
/// Rejected with a message naming the variant: Assimp's shape shorthands (`tess`, `dod`, `hex`,
/// `oct`, `tet`, `icos`, …) and Sense8's NFF dialect (a file starting with `nff`).
/// Of the samples in shared/data/nff, WithCamera.nff and ManyEarthsNotJustOne.nff load; the
/// others use those extensions (or a short `f`) and are rejected.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string_view>

#include "tracegraph/loaders/AffDocument.h"

namespace tg {

/// Parser settings. The limits guard against hostile files; the defaults are far above what
/// the BART scenes need (kitchen: 186 includes, depth 6, ~110k triangles).
struct AffParseOptions {
  /// Segments around a cone or cylinder; an open cone gives 2 triangles per segment (one when a
  /// radius is zero). Clamped to [3, 4096].
  int coneSegments = 16;
  /// Segments around a sphere; it gets coneSegments/2 rings, i.e. 2·S·(S/2 − 1) triangles
  /// (224 for 16). Clamped to [4, 4096].
  int sphereSegments = 16;
  /// Initial detail level: `i n file` is skipped when n is greater (the `d` command sets it).
  int detailLevel = 0;
  /// Maximum include nesting.
  int maxIncludeDepth = 64;
  /// Maximum transform-block nesting (the data reaches 15).
  int maxBlockDepth = 256;
  /// Maximum total bytes parsed, counting every inclusion again (stops include explosions).
  std::uint64_t maxTotalBytes = std::uint64_t{1} << 30;
  /// Maximum number of triangles, including tessellated and animated ones.
  std::uint64_t maxTriangles = 100'000'000;
};

/// Parses an AFF or NFF file and everything it includes. Includes and textures are resolved
/// relative to the folder of the file that names them (textures also in ../TextureFiles/);
/// each included file is read once and re-parsed at every inclusion.
///
/// Throws tg::Error with a message "FILE:LINE: what" for an unreadable file, an unknown command,
/// a missing include, an include cycle, a truncated file, a malformed, NaN or infinite number,
/// an index out of range, a count larger than the rest of the file could hold, unbalanced
/// braces (every file must be balanced on its own) or an exceeded limit of `options`.
AffDocument parseAffFile(const std::filesystem::path& file, const AffParseOptions& options = {});

/// Parses AFF/NFF text held in memory. `baseDir` is where includes and textures are looked up;
/// `displayName` names the text in messages and becomes AffDocument::files[0].
/// Throws tg::Error like parseAffFile.
AffDocument parseAffText(std::string_view text, const std::filesystem::path& baseDir,
                         const AffParseOptions& options = {},
                         std::string_view displayName = "<text>");

}  // namespace tg
