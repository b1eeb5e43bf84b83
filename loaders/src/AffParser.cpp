#include "tracegraph/loaders/AffParser.h"

#include <algorithm>
#include <fstream>
#include <numbers>
#include <system_error>
#include <utility>

#include "AffParserImpl.h"
#include "tracegraph/backend/Error.h"

namespace tg {
namespace aff_detail {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

/// Reads a whole regular file into `out`. Returns an empty string on success, else the reason.
/// Special files (devices, FIFOs, folders) are refused: reading /dev/zero would never end.
std::string readWholeFile(const std::filesystem::path& path, std::uint64_t limit,
                          std::string& out) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return "not a regular file";
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) return "cannot determine its size";
  if (size > limit) return "larger than the parse limit of " + std::to_string(limit) + " bytes";
  std::ifstream in(path, std::ios::binary);
  if (!in) return "cannot open it";
  out.resize(static_cast<std::size_t>(size));
  in.read(out.data(), static_cast<std::streamsize>(size));
  if (static_cast<std::uintmax_t>(in.gcount()) != size) return "read error";
  return {};
}

}  // namespace

AffParserImpl::AffParserImpl(const AffParseOptions& options) : opt_(options) {
  opt_.coneSegments = std::clamp(opt_.coneSegments, 3, 4096);
  opt_.sphereSegments = std::clamp(opt_.sphereSegments, 4, 4096);
  detailLevel_ = opt_.detailLevel;
}

AffDocument AffParserImpl::run(std::string_view text, const std::string& canonicalKey,
                               const std::string& displayName, const std::filesystem::path& dir) {
  doc_.files.emplace_back(displayName);
  if (!canonicalKey.empty()) {
    fileIndex_.emplace(canonicalKey, 0);
    includeChain_.push_back(canonicalKey);
  }
  totalBytes_ = text.size();
  if (totalBytes_ > opt_.maxTotalBytes)
    throw Error(displayName + ": larger than the parse limit of " +
                std::to_string(opt_.maxTotalBytes) + " bytes");
  AffBlock root;
  root.kind = AffBlock::Kind::Root;
  root.where = {0, 1};
  stack_.push_back(std::move(root));
  Source main{0, dir, AffLexer(text), 1};
  parseSource(main);
  doc_.root = std::move(stack_.front());
  return std::move(doc_);
}

void AffParserImpl::parseSource(Source& s) {
  for (;;) {
    const AffToken cmd = s.lex.next();
    if (cmd.atEnd()) break;
    dispatch(s, cmd);
  }
  if (stack_.size() > s.baseDepth) {
    fail(s, s.lex.endLine(),
         "end of file inside the block opened at line " + std::to_string(block().where.line) +
             " (missing '}'; every file must close its own blocks)");
  }
}

void AffParserImpl::dispatch(Source& s, const AffToken& cmd) {
  const std::string_view c = cmd.text;
  // Roughly by frequency in the BART data.
  if (c == "m") return parseMesh(s, cmd);
  if (c == "}") return closeBlock(s, cmd);
  if (c == "xs") return parseStaticBlock(s, cmd);
  if (c == "fm") return parseMaterialFm(s, cmd);
  if (c == "i") return parseInclude(s, cmd);
  if (c == "tpa") return parseAnimatedTriangle(s, cmd);
  if (c == "x") return parseAnimatedBlock(s, cmd);
  if (c == "k") return parseKeyframes(s, cmd);
  if (c == "p") return parsePolygon(s, cmd, false);
  if (c == "pp") return parsePolygon(s, cmd, true);
  if (c == "tt") return parseTexturedTriangle(s, cmd, false);
  if (c == "ttp") return parseTexturedTriangle(s, cmd, true);
  if (c == "c") return parseCone(s, cmd);
  if (c == "s") return parseSphere(s, cmd);
  if (c == "f") return parseMaterialNff(s, cmd);
  if (c == "l") return parseLight(s, cmd, false);
  if (c == "la") return parseLight(s, cmd, true);
  if (c == "v") return parseView(s, cmd);
  if (c == "a") return parseAnimationRange(s, cmd);
  if (c == "b") {
    doc_.background = readVec3f(s, "background colour");
    return;
  }
  if (c == "am") {
    doc_.ambient = readVec3f(s, "global ambient colour");
    return;
  }
  if (c == "d") {
    detailLevel_ = readInt(s, "detail level");
    return;
  }
  if (c == "tess" || c == "dod" || c == "hex" || c == "oct" || c == "tet" || c == "icos" ||
      c == "cone" || c == "cyl" || c == "sph") {
    fail(s, cmd.line,
         "command " + quoteToken(c) + " is an Assimp extension of NFF and is not supported");
  }
  if (c == "nff" || c == "version" || c == "viewpos" || c == "viewdir") {
    fail(s, cmd.line,
         "command " + quoteToken(c) +
             " belongs to the Sense8 NFF dialect, which is not "
             "supported (only Haines' NFF and AFF)");
  }
  if (c == "{") fail(s, cmd.line, "'{' without a block command ('xs', 'x' or 'k') before it");
  fail(s, cmd.line, "unknown command " + quoteToken(c));
}

void AffParserImpl::fail(const Source& s, std::uint32_t line, const std::string& what) const {
  throw Error(doc_.files[s.fileIndex].string() + ":" + std::to_string(line) + ": " + what);
}

void AffParserImpl::addTriangles(const Source& s, std::uint32_t line, std::uint64_t count) {
  totalTriangles_ += count;
  if (totalTriangles_ > opt_.maxTriangles)
    fail(s, line, "more than " + std::to_string(opt_.maxTriangles) + " triangles in total");
}

// --- scene-level commands ---

void AffParserImpl::parseView(Source& s, const AffToken& cmd) {
  AffView v;
  v.present = true;
  v.where = where(s, cmd.line);
  expectKeyword(s, "from", "in 'v'");
  v.from = readVec3d(s, "view 'from'");
  expectKeyword(s, "at", "in 'v'");
  v.at = readVec3d(s, "view 'at'");
  expectKeyword(s, "up", "in 'v'");
  v.up = readVec3d(s, "view 'up'");
  expectKeyword(s, "angle", "in 'v'");
  v.angle = readDouble(s, "view angle");
  expectKeyword(s, "hither", "in 'v'");
  v.hither = readDouble(s, "view hither");
  expectKeyword(s, "resolution", "in 'v'");
  v.width = readInt(s, "view resolution");
  v.height = readInt(s, "view resolution");
  if (v.width < 1 || v.height < 1) fail(s, cmd.line, "view resolution must be positive");
  doc_.view = v;
}

void AffParserImpl::parseLight(Source& s, const AffToken& cmd, bool animated) {
  AffLight l;
  l.where = where(s, cmd.line);
  if (animated) l.track = std::string(readName(s, "light track name"));
  l.position = readVec3d(s, "light position");
  // The colour is optional; commands never start with a number, so a number means colour.
  if (nextIsNumber(s)) {
    l.colour = readVec3f(s, "light colour");
    l.hasColour = true;
  }
  doc_.lights.push_back(std::move(l));
}

void AffParserImpl::parseMaterialFm(Source& s, const AffToken& cmd) {
  AffMaterial m;
  m.ambient = readVec3f(s, "'fm' ambient colour");
  m.diffuse = readVec3f(s, "'fm' diffuse colour");
  m.specular = readVec3f(s, "'fm' specular colour");
  m.shine = readFloat(s, "'fm' shine");
  m.transmittance = readFloat(s, "'fm' transmittance");
  m.ior = readFloat(s, "'fm' index of refraction");
  m.where = where(s, cmd.line);
  material_ = std::move(m);
  nffTexture_.clear();
  plainMaterialIndex_ = -1;
}

void AffParserImpl::parseMaterialNff(Source& s, const AffToken& cmd) {
  const char* what = "NFF 'f' number (f r g b Kd Ks shine T ior)";
  const Vec3f rgb = readVec3f(s, what);
  const float kd = readFloat(s, what);
  const float ks = readFloat(s, what);
  AffMaterial m;
  m.ambient = {0, 0, 0};
  m.diffuse = rgb * kd;
  m.specular = {ks, ks, ks};
  m.shine = readFloat(s, what);
  m.transmittance = readFloat(s, what);
  m.ior = readFloat(s, what);
  m.where = where(s, cmd.line);
  material_ = std::move(m);
  nffTexture_.clear();
  plainMaterialIndex_ = -1;
  // Assimp's samples put a texture name after the numbers, on the same line.
  const AffToken& next = s.lex.peek();
  if (!next.atEnd() && next.line == lastLine_ && !nextIsNumber(s) && next.text != "{" &&
      next.text != "}") {
    nffTexture_ = std::string(s.lex.next().text);
  }
}

void AffParserImpl::parseStaticBlock(Source& s, const AffToken& cmd) {
  AffBlock b;
  b.kind = AffBlock::Kind::Static;
  b.where = where(s, cmd.line);
  b.scale = readVec3d(s, "'xs' scale");
  b.axis = readVec3d(s, "'xs' rotation axis");
  b.degrees = readDouble(s, "'xs' rotation angle");
  b.translation = readVec3d(s, "'xs' translation");
  expectKeyword(s, "{", "after 'xs' and its 10 numbers");
  // M = T·R·S: scale the rotation's columns, then put the translation in the last column.
  Affine3d m = rotationMatrix(b.axis, b.degrees * kDegToRad);
  for (int r = 0; r < 3; ++r) {
    m.m[r][0] *= b.scale.x;
    m.m[r][1] *= b.scale.y;
    m.m[r][2] *= b.scale.z;
    m.m[r][3] = b.translation[static_cast<std::size_t>(r)];
  }
  if (!m.isFinite()) fail(s, cmd.line, "'xs' transform overflows");
  b.matrix = m;
  openBlock(s, std::move(b));
}

void AffParserImpl::parseAnimatedBlock(Source& s, const AffToken& cmd) {
  AffBlock b;
  b.kind = AffBlock::Kind::Animated;
  b.where = where(s, cmd.line);
  b.name = std::string(readName(s, "'x' track name"));
  expectKeyword(s, "{", "after 'x name'");
  openBlock(s, std::move(b));
}

void AffParserImpl::openBlock(Source& s, AffBlock&& b) {
  if (stack_.size() > static_cast<std::size_t>(opt_.maxBlockDepth))
    fail(s, b.where.line, "blocks nested deeper than " + std::to_string(opt_.maxBlockDepth));
  stack_.push_back(std::move(b));
}

void AffParserImpl::closeBlock(Source& s, const AffToken& cmd) {
  if (stack_.size() <= s.baseDepth)
    fail(s, cmd.line, "'}' without a matching block opened in this file");
  AffBlock b = std::move(stack_.back());
  stack_.pop_back();
  block().children.push_back(std::move(b));
}

void AffParserImpl::parseAnimationRange(Source& s, const AffToken& cmd) {
  AffAnimation a;
  a.present = true;
  a.where = where(s, cmd.line);
  a.start = readDouble(s, "animation start time");
  a.end = readDouble(s, "animation end time");
  a.frames = readInt(s, "animation frame count");
  if (a.frames < 1) fail(s, cmd.line, "animation frame count must be at least 1");
  doc_.animation = a;
}

void AffParserImpl::parseKeyframes(Source& s, const AffToken& cmd) {
  AffTrack track;
  track.where = where(s, cmd.line);
  track.name = std::string(readName(s, "'k' track name"));
  expectKeyword(s, "{", "after 'k name'");
  const auto readTcb = [&](KbParams& p) {
    p.tension = readDouble(s, "key tension");
    p.continuity = readDouble(s, "key continuity");
    p.bias = readDouble(s, "key bias");
  };
  for (;;) {
    const AffToken t = s.lex.next();
    if (t.atEnd()) {
      fail(s, t.line,
           "unexpected end of file in keyframe block " + quoteToken(track.name) +
               " opened at line " + std::to_string(cmd.line));
    }
    if (t.text == "}") break;
    const bool isTransl = t.text == "transl", isScale = t.text == "scale";
    if (isTransl || isScale) {
      auto& channel = isTransl ? track.translation : track.scale;
      if (channel)
        fail(s, t.line, quoteToken(t.text) + " given twice in track " + quoteToken(track.name));
      const std::uint32_t n = readCount(s, "key count", 7);
      if (n < 4) fail(s, t.line, quoteToken(t.text) + " needs at least 4 keys");
      std::vector<KbVectorSpline::Key> keys(n);
      for (KbVectorSpline::Key& k : keys) {
        k.time = readDouble(s, "key time");
        k.value = readVec3d(s, isTransl ? "translation key" : "scale key");
        readTcb(k.tcb);
      }
      channel.emplace(std::move(keys));
    } else if (t.text == "rot") {
      if (track.rotation) fail(s, t.line, "'rot' given twice in track " + quoteToken(track.name));
      const std::uint32_t n = readCount(s, "key count", 8);
      if (n < 4) fail(s, t.line, "'rot' needs at least 4 keys");
      std::vector<KbRotationSpline::Key> keys(n);
      for (KbRotationSpline::Key& k : keys) {
        k.time = readDouble(s, "key time");
        k.axis = readVec3d(s, "rotation key axis");
        k.degrees = readDouble(s, "rotation key angle");
        readTcb(k.tcb);
      }
      track.rotation.emplace(std::move(keys));
    } else if (t.text == "visibility") {
      if (!track.visibility.empty())
        fail(s, t.line, "'visibility' given twice in track " + quoteToken(track.name));
      const std::uint32_t n = readCount(s, "key count", 2);
      track.visibility.resize(n);
      for (VisibilityKey& k : track.visibility) {
        k.time = readDouble(s, "key time");
        const int flag = readInt(s, "visibility flag");
        if (flag != 0 && flag != 1) fail(s, lastLine_, "visibility flag must be 0 or 1");
        k.visible = flag == 1;
      }
    } else {
      fail(s, t.line,
           "unknown keyframe channel " + quoteToken(t.text) + " in track " +
               quoteToken(track.name) + " (expected transl, rot, scale or visibility)");
    }
  }
  const auto it = doc_.tracks.find(track.name);
  if (it != doc_.tracks.end()) {
    // The same text included again (kitchen's wheels) is not worth a warning.
    const AffSourceLocation& before = it->second.where;
    if (before.file != track.where.file || before.line != track.where.line) {
      doc_.warnings.push_back(doc_.describe(track.where) + ": track " + quoteToken(track.name) +
                              " defined again (first at " + doc_.describe(before) +
                              "); the last definition is used");
    }
    it->second = std::move(track);
  } else {
    std::string name = track.name;
    doc_.tracks.emplace(std::move(name), std::move(track));
  }
}

void AffParserImpl::parseInclude(Source& s, const AffToken& cmd) {
  const int detail = readInt(s, "include detail level");
  const std::string name(readName(s, "include file name"));
  if (detail > detailLevel_) return;
  if (includeChain_.size() > static_cast<std::size_t>(opt_.maxIncludeDepth))
    fail(s, cmd.line, "includes nested deeper than " + std::to_string(opt_.maxIncludeDepth));
  const std::filesystem::path path = s.dir / std::filesystem::path(name);
  // canonical() costs several system calls; robots includes 835 times from ~50 distinct names.
  std::string resolveKey = s.dir.string();
  resolveKey += '\n';
  resolveKey += name;
  auto resolved = canonicalCache_.find(resolveKey);
  if (resolved == canonicalCache_.end()) {
    std::error_code ec;
    std::filesystem::path canon = std::filesystem::canonical(path, ec);
    if (ec) fail(s, cmd.line, "missing include " + quoteToken(name) + " (" + path.string() + ")");
    resolved = canonicalCache_.emplace(std::move(resolveKey), std::move(canon)).first;
  }
  const std::filesystem::path& canon = resolved->second;
  const std::string key = canon.string();
  if (std::find(includeChain_.begin(), includeChain_.end(), key) != includeChain_.end()) {
    std::string chain;
    const auto from = std::find(includeChain_.begin(), includeChain_.end(), key);
    for (auto it = from; it != includeChain_.end(); ++it)
      chain += std::filesystem::path(*it).filename().string() + " -> ";
    fail(s, cmd.line, "include cycle: " + chain + canon.filename().string());
  }
  const std::string& text = loadText(s, cmd.line, key);
  totalBytes_ += text.size();
  if (totalBytes_ > opt_.maxTotalBytes) {
    fail(s, cmd.line,
         "included text exceeds " + std::to_string(opt_.maxTotalBytes) +
             " bytes in total (too many inclusions)");
  }
  const auto [indexIt, inserted] =
      fileIndex_.try_emplace(key, static_cast<std::uint32_t>(doc_.files.size()));
  if (inserted) doc_.files.push_back(path.lexically_normal());
  ++doc_.includeCount;
  Source child{indexIt->second, canon.parent_path(), AffLexer(text), stack_.size()};
  includeChain_.push_back(key);
  parseSource(child);
  includeChain_.pop_back();
}

const std::string& AffParserImpl::loadText(const Source& s, std::uint32_t line,
                                           const std::string& key) {
  const auto it = texts_.find(key);
  if (it != texts_.end()) return it->second;
  std::string text;
  const std::string problem = readWholeFile(key, opt_.maxTotalBytes, text);
  if (!problem.empty()) fail(s, line, "cannot read include " + key + ": " + problem);
  // Node-based map: the string (and views into it) stay put when the map grows.
  return texts_.emplace(key, std::move(text)).first->second;
}

}  // namespace aff_detail

AffDocument parseAffFile(const std::filesystem::path& file, const AffParseOptions& options) {
  std::error_code ec;
  const std::filesystem::path canon = std::filesystem::canonical(file, ec);
  if (ec) throw Error(file.string() + ": cannot open AFF/NFF file (" + ec.message() + ")");
  std::string text;
  const std::string problem = aff_detail::readWholeFile(canon, options.maxTotalBytes, text);
  if (!problem.empty()) throw Error(file.string() + ": cannot read AFF/NFF file: " + problem);
  aff_detail::AffParserImpl parser(options);
  return parser.run(text, canon.string(), file.lexically_normal().string(), canon.parent_path());
}

AffDocument parseAffText(std::string_view text, const std::filesystem::path& baseDir,
                         const AffParseOptions& options, std::string_view displayName) {
  aff_detail::AffParserImpl parser(options);
  return parser.run(text, std::string(), std::string(displayName), baseDir);
}

}  // namespace tg
