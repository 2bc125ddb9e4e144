#pragma once
/// The resume cache of a font report (`cmr report FAMILY.designspace --out
/// DIR`, a UFO, a font, a variable font; issue 37): DIR/report.cache holds,
/// per glyph, what the report writes of it (its spline objects' JSON text,
/// its findings, its statuses, its row and section of the font page),
/// under a key that hashes everything the glyph's verdict depends on. A
/// rerun reuses a glyph whose key is in the cache and judges the others, and
/// its report is byte for byte the one a fresh run writes (corpus.cpp).
///
/// The key (SHA-256) covers: the cache format, the build of cmr that judges
/// (build_id: the SHA-256 of the executable or module holding this code, so
/// any rebuild with a change misses), the report's options (every field of
/// ReportOptions and the BatchOptions that change a glyph's output), the
/// file's name as the report spells it (findings, SARIF, the page), the
/// font's own header (family, style, units per em, outlines, missing
/// characters), and the glyph as it was read: each contour's points, knots
/// and name, its node and point names and source lines, its .glif, and, for
/// the interpolation gates, its splines at both ends of every piece with
/// their smooth marks and the pieces' axes and locations. So the key is
/// taken over what the judge reads of each glyph in every master, not over
/// the file's bytes: a .glif edited in one master changes that glyph's key
/// only; an edit that changes nothing read (a comment) keeps it.
///
/// The file is one of the report's outputs, staged and committed with the
/// rest of the output set (io/output.hpp): it is there whole, with the run's
/// report.json, or the previous one stays. Its format:
///
///   "cmr report cache 1\n" BUILD_ID_HEX "\n"
///   then records: key (32 bytes), payload length (8 bytes, little endian),
///   SHA-256 of the payload (32 bytes), payload (encode()).
///
/// A cache is ignored, with one note, when it is not this user's own regular
/// file (never read through a link), is not a cache (another header), was
/// written by another build of cmr, or is cut short or inconsistent; a
/// record whose payload does not match its checksum or does not decode is
/// that glyph judged again (one note for the run). Nothing is trusted that
/// its checksum does not cover.
#include <array>
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "report/corpus.hpp"
#include "report/font_report.hpp"

namespace cmr::report {

/// The name of the cache in a report's output folder.
inline constexpr const char* kReportCacheName = "report.cache";

using CacheKey = std::array<std::uint8_t, 32>;

/// SHA-256 (FIPS 180-4) over the bytes added; add() writes each value in a
/// fixed, unambiguous form (a string with its length first, a double as its
/// bits), so that two different sequences of values never hash alike by
/// concatenation.
class KeyHasher {
 public:
  KeyHasher();
  KeyHasher& bytes(const void* data, std::size_t n);
  KeyHasher& add(std::string_view s);
  KeyHasher& add(std::uint64_t v);
  KeyHasher& add(double v);
  KeyHasher& add_int(long long v) { return add(static_cast<std::uint64_t>(v)); }
  CacheKey finish();

 private:
  void block(const std::uint8_t* p);
  std::array<std::uint32_t, 8> h_{};
  std::array<std::uint8_t, 64> buf_{};
  std::size_t used_ = 0;
  std::uint64_t total_ = 0;
};

/// Lowercase hexadecimal of `k`.
std::string hex(const CacheKey& k);

/// The build id: hex SHA-256 of the file this code was loaded from (the
/// cmr executable, or the Python module), computed once per process. ""
/// when it cannot be read: then nothing is cached.
const std::string& build_id();

/// One report item (contour) of a glyph, as the report writes it.
struct CachedItem {
  std::string json;  ///< its spline object, the id "s0" (corpus.cpp numbers it)
  std::vector<Finding> findings;
  std::string error;  ///< invalid: why
  bool pass = false;
  std::vector<bool> gate_pass;  ///< per gate of the run
};

/// One glyph of a font file as the report writes it.
struct CachedGlyph {
  std::vector<CachedItem> items;
  GlyphHtml html;
};

/// The payload of a record, and back (false when `bytes` is not one).
std::string encode(const CachedGlyph& g);
bool decode(std::string_view bytes, CachedGlyph& g);

/// The previous run's cache, opened read-only before the run writes its
/// own (the commit renames the new one over it; the open file stays the
/// old one). find() is safe from several threads.
class ReportCache {
 public:
  ReportCache() = default;
  ReportCache(const ReportCache&) = delete;
  ReportCache& operator=(const ReportCache&) = delete;
  ~ReportCache();
  /// Opens `file` when it is there. `note` is set when it is there but
  /// ignored ("FILE: ignored: ..."); a cache that is not there is no note.
  void open(const std::filesystem::path& file, std::string& note);
  bool usable() const { return fd_ >= 0; }
  std::size_t size() const { return index_.size(); }
  /// The glyph stored under `key`, when there is a record and it checks.
  std::optional<CachedGlyph> find(const CacheKey& key) const;
  /// The note of find()'s failures ("" when none).
  std::string damage_note() const;

 private:
  struct Record {
    std::uint64_t offset = 0, length = 0;
    CacheKey checksum{};
  };
  struct KeyHash {
    std::size_t operator()(const CacheKey& k) const;
  };
  std::filesystem::path file_;
  int fd_ = -1;
  std::unordered_map<CacheKey, Record, KeyHash> index_;
  mutable std::atomic<int> damaged_{0};
};

/// The header of a cache file written by this build.
std::string cache_header();

/// The record of one glyph.
std::string cache_record(const CacheKey& key, const CachedGlyph& g);

/// The part of every glyph's key that the whole run shares: the cache
/// format, build_id(), and the options that change a glyph's output.
std::string run_key_prefix(const BatchOptions& options);

/// A glyph's key: `file_prefix` (run_key_prefix, then the file's name, URI
/// and font header: file_key_prefix), then the glyph as read.
std::string file_key_prefix(const std::string& run_prefix, const std::string& path, const std::string& name,
                            const std::string& uri, bool uri_relative, const FontInfo& font);
CacheKey glyph_key(const std::string& file_prefix, const FontInfo::GlyphEntry& glyph,
                   const std::vector<ReportInput>& inputs);

}  // namespace cmr::report
