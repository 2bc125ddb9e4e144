// The bivariate certificate of curvature-between-masters on a real family
// (issue 37, Speed): every segment of every glyph, on every piece where its
// points move affinely (io/masters.hpp read_masters, as cmr report reads
// them), judged by monotone_between (bezierize/between.hpp) when its
// curvature is monotone at both ends of the piece. Prints the pieces'
// verdicts, the share of (t, s) cells decided by the floating-point bound
// and by the exact path, and the time (one thread: the certificate's own
// cost; cmr report adds the rest and --jobs).
//   build/tools/bench/bench_between FAMILY.designspace|VF.ttf [GLYPHS]
// GLYPHS as cmr report's --glyphs (default A-Z,a-z; "all": every glyph).
// Glyphs the reader refuses (incompatible masters) are counted and skipped.
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <optional>
#include <string>

#include "bezierize/between.hpp"
#include "bezierize/extract.hpp"
#include "io/font.hpp"
#include "io/masters.hpp"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_between FAMILY.designspace|VF.ttf [GLYPHS]\n");
    return 2;
  }
  try {
    cmr::import::GlyphSelection which;
    const std::string spec = argc > 2 ? argv[2] : "A-Z,a-z";
    if (spec == "all")
      which.all = true;
    else
      which.codepoints = cmr::import::parse_glyph_spec(spec);
    const auto t0 = std::chrono::steady_clock::now();
    const cmr::import::Masters m = cmr::import::read_masters(argv[1], which, std::nullopt);
    const double read_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::int64_t segments = 0, judged = 0, holds = 0, fails = 0, undecided = 0, not_monotone = 0;
    std::int64_t cells_float = 0, cells_exact = 0, pieces_exact = 0;
    int refused = 0;
    const cmr::BetweenOptions options;
    const auto t1 = std::chrono::steady_clock::now();
    for (std::size_t g = 0; g < m.font.glyphs.size(); ++g) {
      if (!m.font.glyphs[g].error.empty()) {
        ++refused;
        continue;
      }
      for (const auto& contour : m.motions[g])
        for (const cmr::import::ContourMotion& motion : contour) {
          if (motion.a.is_rational() || motion.a.degree() < 2) continue;
          for (int i = 0; i < motion.a.segment_count(); ++i) {
            ++segments;
            const auto A = cmr::segment_bezier_points<double>(motion.a, motion.a.segments()[i]);
            const auto B = cmr::segment_bezier_points<double>(motion.b, motion.b.segments()[i]);
            using K = cmr::BetweenVerdict::Kind;
            if (cmr::monotone_between(A, A, options).kind != K::holds_throughout ||
                cmr::monotone_between(B, B, options).kind != K::holds_throughout) {
              ++not_monotone;
              continue;
            }
            ++judged;
            const cmr::BetweenVerdict v = cmr::monotone_between(A, B, options);
            cells_float += v.cells_float;
            cells_exact += v.cells_exact;
            pieces_exact += v.cells_exact > 0;
            (v.kind == K::holds_throughout ? holds : v.kind == K::fails ? fails : undecided) += 1;
          }
        }
    }
    const double judge_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
    const double cells = static_cast<double>(cells_float + cells_exact);
    std::printf("%s (%s): %zu glyphs (%d refused by the reader), %zu pieces of the design space\n", argv[1],
                spec.c_str(), m.font.glyphs.size(), refused, m.pieces.size());
    std::printf("segment-pieces: %lld, monotone at both ends: %lld (certified %lld, fails %lld, undecided %lld); "
                "not monotone at an end: %lld\n",
                static_cast<long long>(segments), static_cast<long long>(judged), static_cast<long long>(holds),
                static_cast<long long>(fails), static_cast<long long>(undecided),
                static_cast<long long>(not_monotone));
    std::printf("cells: %lld by the floating-point bound (%.2f%%), %lld by the exact path (%.2f%%); "
                "segment-pieces that needed the exact path: %lld (%.2f%%)\n",
                static_cast<long long>(cells_float), cells > 0 ? 100.0 * cells_float / cells : 0.0,
                static_cast<long long>(cells_exact), cells > 0 ? 100.0 * cells_exact / cells : 0.0,
                static_cast<long long>(pieces_exact), judged > 0 ? 100.0 * pieces_exact / judged : 0.0);
    std::printf("time: read %.2f s, certificates %.2f s (one thread)\n", read_s, judge_s);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_between: %s\n", e.what());
    return 2;
  }
}
