/// @file AffParserImpl.h
/// The AFF/NFF parser's state machine (private to the loaders library). Scene-level commands,
/// includes and keyframes live in AffParser.cpp, token reading in AffParseTokens.cpp and
/// geometry commands in AffParseGeometry.cpp.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "AffLexer.h"
#include "tracegraph/loaders/AffDocument.h"
#include "tracegraph/loaders/AffParser.h"

namespace tg::aff_detail {

/// Parses strtod-style decimal numbers ("-.279", "3.", "2.6E-4", an optional leading '+').
/// Returns false for anything else; NaN and infinity parse (the caller rejects them so that
/// the message can say why).
bool parseDouble(std::string_view token, double& out);

/// Quotes a token for an error message: non-printable bytes as \xNN, long tokens shortened.
std::string quoteToken(std::string_view token);

/// Parser state for one document. Not reusable: construct, call run(), discard.
class AffParserImpl {
 public:
  /// Prepares a parse with the given (clamped) options.
  explicit AffParserImpl(const AffParseOptions& options);

  /// Parses `text` as the main file. `canonicalKey` identifies it for cycle detection (empty
  /// for in-memory text), `displayName` names it in messages, includes resolve against `dir`.
  AffDocument run(std::string_view text, const std::string& canonicalKey,
                  const std::string& displayName, const std::filesystem::path& dir);

 private:
  /// One file being parsed (the main text or an inclusion).
  struct Source {
    std::uint32_t fileIndex;    ///< index into AffDocument::files
    std::filesystem::path dir;  ///< folder for includes and textures
    AffLexer lex;               ///< tokens of this inclusion
    std::size_t baseDepth;      ///< block-stack depth when the file started
  };

  // --- driver and errors (AffParser.cpp) ---
  void parseSource(Source& s);
  void dispatch(Source& s, const AffToken& cmd);
  [[noreturn]] void fail(const Source& s, std::uint32_t line, const std::string& what) const;
  AffSourceLocation where(const Source& s, std::uint32_t line) const { return {s.fileIndex, line}; }
  AffBlock& block() { return stack_.back(); }
  void addTriangles(const Source& s, std::uint32_t line, std::uint64_t count);

  // --- token readers (AffParseTokens.cpp) ---
  AffToken expectToken(Source& s, const char* what);
  void expectKeyword(Source& s, std::string_view keyword, const char* context);
  double readDouble(Source& s, const char* what);
  float readFloat(Source& s, const char* what);
  Vec3d readVec3d(Source& s, const char* what);
  Vec3f readVec3f(Source& s, const char* what);
  int readInt(Source& s, const char* what);
  /// Reads a count of items that each need at least `tokensPerItem` more tokens, and rejects
  /// it unless the rest of the file could hold that many (every token takes at least one
  /// byte plus one separator), so no allocation is ever sized by an unchecked number.
  std::uint32_t readCount(Source& s, const char* what, std::uint32_t tokensPerItem);
  std::uint32_t readIndex(Source& s, std::uint32_t limit, const char* what);
  std::string_view readName(Source& s, const char* what);
  bool nextIsNumber(Source& s);

  // --- scene-level commands (AffParser.cpp) ---
  void parseView(Source& s, const AffToken& cmd);
  void parseLight(Source& s, const AffToken& cmd, bool animated);
  void parseMaterialFm(Source& s, const AffToken& cmd);
  void parseMaterialNff(Source& s, const AffToken& cmd);
  void parseStaticBlock(Source& s, const AffToken& cmd);
  void parseAnimatedBlock(Source& s, const AffToken& cmd);
  void openBlock(Source& s, AffBlock&& b);
  void closeBlock(Source& s, const AffToken& cmd);
  void parseAnimationRange(Source& s, const AffToken& cmd);
  void parseKeyframes(Source& s, const AffToken& cmd);
  void parseInclude(Source& s, const AffToken& cmd);
  const std::string& loadText(const Source& s, std::uint32_t line, const std::string& key);

  // --- geometry (AffParseGeometry.cpp) ---
  void parseMesh(Source& s, const AffToken& cmd);
  void parsePolygon(Source& s, const AffToken& cmd, bool withNormals);
  void parseTexturedTriangle(Source& s, const AffToken& cmd, bool withNormals);
  void parseCone(Source& s, const AffToken& cmd);
  void parseSphere(Source& s, const AffToken& cmd);
  void parseAnimatedTriangle(Source& s, const AffToken& cmd);
  /// Material-table index of the current material with this texture (may be empty; then an
  /// NFF `f` texture applies unless `untextured`).
  std::uint32_t materialFor(const Source& s, std::uint32_t line, std::string_view texture,
                            bool untextured);
  std::filesystem::path resolveTexture(const Source& s, std::uint32_t line,
                                       std::string_view texture);

  AffParseOptions opt_;
  AffDocument doc_;
  std::vector<AffBlock> stack_;  ///< open blocks; [0] is the root

  // Global state the format does not scope: material, NFF texture, detail level.
  AffMaterial material_;                  ///< current `fm`/`f` (texture fields unused)
  std::string nffTexture_;                ///< texture named after an NFF `f`
  std::int64_t plainMaterialIndex_ = -1;  ///< cached table index of material_ untextured
  int detailLevel_ = 0;

  /// Material table lookup: the numbers of an entry plus its texture name and folder.
  using MaterialKey = std::pair<std::array<float, 12>, std::string>;
  std::map<MaterialKey, std::uint32_t> materialIndex_;
  std::unordered_map<std::string, std::filesystem::path> textureCache_;

  // Includes: texts read once, keyed by canonical path, and the chain being parsed.
  std::unordered_map<std::string, std::string> texts_;
  std::unordered_map<std::string, std::uint32_t> fileIndex_;
  std::unordered_map<std::string, std::filesystem::path> canonicalCache_;  ///< dir + name → file
  std::vector<std::string> includeChain_;
  std::uint64_t totalBytes_ = 0;
  std::uint64_t totalTriangles_ = 0;
  std::uint32_t lastLine_ = 0;  ///< line of the last token taken by expectToken
};

}  // namespace tg::aff_detail
