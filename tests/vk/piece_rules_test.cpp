// The shader's piece decision (shaders/piece_rules.glsl, run on lavapipe in
// fp64 and fp32) against the C++ core's (bezierize/decide.hpp), case by case,
// on one table of coefficient vectors with error bounds: certain signs,
// exact zeros and values inside their bound (uncertain), for both
// algorithms, cubic sizes (6 xi, 3 nu), quartic sizes (10 xi, 5 nu) and 1.
#include "bezierize/decide.hpp"
#include "vk/fragment_pipeline.hpp"

#include "piece_rules_test_fp32_frag.h"
#include "piece_rules_test_fp64_frag.h"
#include "device_under_test.hpp"

#include <gtest/gtest.h>

#include <string>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <random>
#include <span>
#include <sstream>
#include <vector>

namespace cmr {
namespace {

/// Context options naming a device (designated initializers would leave the
/// other members to -Wmissing-field-initializers).
vk::ContextOptions test_options(const std::string& device, bool require_float64 = true) {
  vk::ContextOptions o;
  o.device_name = device;
  o.require_float64 = require_float64;
  return o;
}

constexpr int kMaxN1 = 10;
constexpr int kStride = 1 + kMaxN1;  // CASE_STRIDE of the test shader
constexpr uint32_t kColumns = 256;   // COLUMNS of the test shader

struct Case {
  bool eta = false;
  std::vector<Bounded> c;
};

// Coefficient kinds, all exact in fp32: certainly +, certainly -, an exact
// zero, and three values inside their bound (uncertain).
const Bounded kKinds[] = {{2.0, 1.0}, {-3.0, 0.5}, {0.0, 0.0}, {0.25, 1.0}, {-0.5, 1.0}, {0.0, 0.125}};
constexpr int kKindCount = 6;

std::vector<Case> table() {
  std::vector<Case> out;
  auto add_both = [&](const std::vector<Bounded>& c) {
    out.push_back({false, c});
    out.push_back({true, c});
  };
  for (int n1 : {1, 3, 5}) {  // every combination of kinds
    int total = 1;
    for (int i = 0; i < n1; ++i) total *= kKindCount;
    for (int code = 0; code < total; ++code) {
      std::vector<Bounded> c;
      for (int i = 0, r = code; i < n1; ++i, r /= kKindCount) c.push_back(kKinds[r % kKindCount]);
      add_both(c);
    }
  }
  std::mt19937 rng(20240924);  // seeded: the same table on every run
  for (int n1 : {6, 10}) {
    for (int t = 0; t < 2000; ++t) {
      std::vector<Bounded> c;
      // Mostly certain signs, so that splits and leaves appear, with ends of every kind.
      for (int i = 0; i < n1; ++i) {
        const int k = (i == 0 || i == n1 - 1) ? static_cast<int>(rng() % kKindCount)
                                              : (rng() % 4 == 0 ? static_cast<int>(rng() % kKindCount)
                                                                : static_cast<int>(rng() % 2));
        c.push_back(kKinds[k]);
      }
      add_both(c);
    }
  }
  return out;
}

// The C++ core on one case: a source over the coefficients, scanned as every
// path scans, decided by the one table.
struct VectorSource {
  const std::vector<Bounded>& c;
  int size() const { return static_cast<int>(c.size()); }
  int sign(int k) const { return certain_sign(c[k]); }
};

Piece core_piece(const Case& k) {
  VectorSource src{k.c};
  const SignSummary s = scan_signs(src);
  return k.eta ? inflection_piece(s) : monotonicity_piece(s);
}

template <class F>
std::vector<std::byte> pack(const std::vector<Case>& cases) {
  std::vector<F> v(cases.size() * kStride * 2, F(0));
  for (std::size_t i = 0; i < cases.size(); ++i) {
    F* at = v.data() + i * kStride * 2;
    at[0] = static_cast<F>(cases[i].c.size());
    at[1] = cases[i].eta ? F(1) : F(0);
    for (std::size_t k = 0; k < cases[i].c.size(); ++k) {
      at[2 + 2 * k] = static_cast<F>(cases[i].c[k].v);
      at[3 + 2 * k] = static_cast<F>(cases[i].c[k].e);
    }
  }
  const auto bytes = std::as_bytes(std::span(v));
  return {bytes.begin(), bytes.end()};
}

std::string describe(const Case& k) {
  std::ostringstream s;
  s << (k.eta ? "Algorithm 2" : "Algorithm 1") << " on";
  for (const Bounded& b : k.c) s << " (" << b.v << " +- " << b.e << ")";
  return s.str();
}

void compare(std::span<const uint32_t> spirv, bool fp64) {
  auto context = vk::Context::create(test_options(cmr::vk::test::device_under_test()));
  ASSERT_TRUE(context) << context.error().message;
  std::vector<Case> cases = table();
  const auto rows = static_cast<uint32_t>((cases.size() + kColumns - 1) / kColumns);
  cases.resize(std::size_t{rows} * kColumns, Case{false, {Bounded(1.0, 0.0)}});  // fill the last row
  const uint32_t spec[] = {kStride, kColumns};
  auto pipeline = vk::FragmentPipeline::create(context.value(), spirv, kColumns, rows, 0,
                                               vk::FragmentPipeline::kDefaultBandRows, spec);
  ASSERT_TRUE(pipeline) << pipeline.error().message;
  const std::vector<std::byte> data = fp64 ? pack<double>(cases) : pack<float>(cases);
  auto got = pipeline.value().run(data);
  ASSERT_TRUE(got) << got.error().message;
  int wrong = 0;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const Piece want = core_piece(cases[i]);
    const uint32_t g = got.value()[i];
    if (g == static_cast<uint32_t>(want)) continue;
    if (++wrong <= 10)
      ADD_FAILURE() << "case " << i << ", " << describe(cases[i]) << ": shader "
                    << (g < 8 ? to_string(static_cast<Piece>(g)) : "?") << ", core " << to_string(want);
  }
  EXPECT_EQ(wrong, 0) << "of " << cases.size() << " cases";
}

TEST(PieceRules, TableCoversEveryOutcome) {
  bool seen[8] = {};
  for (const Case& k : table()) seen[static_cast<int>(core_piece(k))] = true;
  for (int p = 0; p < 8; ++p) EXPECT_TRUE(seen[p]) << "no case decides " << to_string(static_cast<Piece>(p));
}

TEST(PieceRules, ShaderFp64MatchesCore) { compare(cmr_piece_rules_test_fp64_frag_spv, true); }
TEST(PieceRules, ShaderFp32MatchesCore) { compare(cmr_piece_rules_test_fp32_frag_spv, false); }

// The rules these tests check are the ones every region shader runs: the
// planar (region_common.glsl) and space (space_region_fp64.comp) shaders
// include piece_rules.glsl and bounded.glsl and define neither the piece
// rules, the certain sign nor the bounded arithmetic themselves.
TEST(PieceRules, EveryRegionShaderIncludesTheSharedRules) {
  for (const char* name : {"region_common.glsl", "space_region_fp64.comp"}) {
    const std::string path = std::string(CMR_SOURCE_DIR) + "/shaders/" + name;
    std::ifstream in(path);
    ASSERT_TRUE(in) << path;
    std::stringstream text;
    text << in.rdbuf();
    const std::string src = text.str();
    EXPECT_NE(src.find("#include \"piece_rules.glsl\""), std::string::npos) << name;
    EXPECT_NE(src.find("#include \"bounded.glsl\""), std::string::npos) << name;
    for (const char* own : {"int b_sign(", "int ends_opposite(", "int ends_touch(", "int monotonicity_rule(",
                            "REAL2 b_add(", "REAL2 b_sub(", "REAL2 b_mul(", "REAL2 b_half(", "SIGN_UNKNOWN ="})
      EXPECT_EQ(src.find(own), std::string::npos) << name << " defines its own " << own;
  }
}

}  // namespace
}  // namespace cmr
