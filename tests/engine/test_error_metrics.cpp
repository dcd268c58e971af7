// The accuracy metrics behind the bench figures: per-row F errors and radiosity errors on hand-made
// matrices whose every figure is known.
#include "support.hpp"

#include "engine/error.hpp"
#include "engine/error_metrics.hpp"

#include <doctest/doctest.h>

using namespace hemirad;
using namespace hemirad::test;

namespace {

FormFactors matrix(std::vector<std::vector<FormFactors::Entry>> rows, std::vector<std::uint8_t> computed) {
    return FormFactors::fromRows(std::move(rows), std::move(computed));
}

}  // namespace

TEST_CASE("F errors: per-row mean, max, RMS and L1 over all N columns, averaged and worst, uncomputed rows left out") {
    // N = 4. Row 0: F has 0.3 at column 1, the reference 0.1 at column 1 and 0.2 at column 2:
    // |dF| = (0, 0.2, 0.2, 0). Row 1: identical. Row 2: |dF| = (0, 0, 0, 0.4). Row 3: not computed in F.
    const FormFactors F = matrix({{{1, 0.3f}}, {{0, 0.5f}}, {}, {}}, {1, 1, 1, 0});
    const FormFactors ref = matrix({{{1, 0.1f}, {2, 0.2f}}, {{0, 0.5f}}, {{3, 0.4f}}, {{0, 1.0f}}}, {1, 1, 1, 1});
    const FormFactorError e = compareFormFactors(F, ref);
    CHECK(e.rows == 3);
    const double tol = 1e-7;  // float entries
    // Row means: 0.4/4, 0, 0.4/4 -> average 0.2/3, worst 0.1.
    CHECK(e.mean == doctest::Approx(0.2 / 3).epsilon(tol));
    CHECK(e.worstMean == doctest::Approx(0.1).epsilon(tol));
    // Row maxima: 0.2, 0, 0.4 -> average 0.2, worst 0.4.
    CHECK(e.max == doctest::Approx(0.2).epsilon(tol));
    CHECK(e.worstMax == doctest::Approx(0.4).epsilon(tol));
    // Row RMS: sqrt(0.08/4), 0, sqrt(0.16/4) -> average (sqrt(0.02) + 0.2) / 3, worst 0.2.
    CHECK(e.rms == doctest::Approx((std::sqrt(0.02) + 0.2) / 3).epsilon(tol));
    CHECK(e.worstRms == doctest::Approx(0.2).epsilon(tol));
    // Row L1: 0.4, 0, 0.4 -> average 0.8/3, worst 0.4 (row 0 first).
    CHECK(e.rowL1 == doctest::Approx(0.8 / 3).epsilon(tol));
    CHECK(e.worstRowL1 == doctest::Approx(0.4).epsilon(tol));
    CHECK((e.worstRow == 0 || e.worstRow == 2));
    // Against itself: all zero.
    const FormFactorError same = compareFormFactors(ref, ref);
    CHECK(same.rows == 4);
    CHECK(same.rowL1 == 0.0);
    CHECK(same.worstMax == 0.0);
    CHECK_THROWS_WITH_AS(compareFormFactors(F, matrix({{}}, {1})), doctest::Contains("F has 4 rows, the reference 1"), Error);
}

TEST_CASE("Radiosity errors: absolute over patches and channels, relative to the reference's mean magnitude") {
    const std::vector<Rgb> ref = {Rgb(1, 2, 3), Rgb(4, 5, 6)};  // mean |B_ref| = 3.5
    const std::vector<Rgb> B = {Rgb(1, 2, 3.6), Rgb(4, 4.7, 6)};  // errors 0.6 and 0.3, four zeros
    const RadiosityError e = compareRadiosity(B, ref);
    CHECK(e.mean == doctest::Approx(0.9 / 6));
    CHECK(e.max == doctest::Approx(0.6));
    CHECK(e.rms == doctest::Approx(std::sqrt((0.36 + 0.09) / 6)));
    CHECK(e.relativeMean == doctest::Approx(0.9 / 6 / 3.5));
    CHECK(e.relativeMax == doctest::Approx(0.6 / 3.5));
    CHECK(e.relativeRms == doctest::Approx(std::sqrt((0.36 + 0.09) / 6) / 3.5));
    const RadiosityError black = compareRadiosity({Rgb::Zero()}, {Rgb::Zero()});
    CHECK(black.relativeMean == 0.0);  // no reference brightness: no relative error, not NaN
    CHECK_THROWS_WITH_AS(compareRadiosity(B, {Rgb::Zero()}), doctest::Contains("different sizes"), Error);
}
