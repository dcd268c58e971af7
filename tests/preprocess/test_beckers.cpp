// Beckers & Beckers partitions: the published cumulative counts and equal projected areas.
#include "preprocess/hemisphere/beckers.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <map>

using namespace hemirad;

TEST_CASE("Beckers disk counts match the published partitions for N = 96 ... 3072") {
    const std::map<std::uint32_t, std::vector<std::uint32_t>> table = {
        {96, {1, 7, 20, 39, 64, 96}},
        {384, {1, 13, 29, 51, 80, 115, 156, 204, 258, 318, 384}},
        {768, {1, 8, 22, 42, 68, 100, 138, 183, 234, 291, 355, 425, 501, 584, 673, 768}},
        {1536, {1, 14, 30, 53, 82, 117, 159, 207, 261, 321, 388, 461, 540, 626, 718, 816, 920, 1031, 1148, 1271, 1400,
                1536}},
        {3072, {1,    16,   33,   57,   87,   123,  166,  215,  270,  331,  399,  473,  553,  640,  733, 832,
                937,  1049, 1167, 1291, 1422, 1559, 1702, 1851, 2007, 2169, 2337, 2511, 2692, 2879, 3072}}};
    for (const auto& [N, S] : table) {
        CAPTURE(N);
        CHECK(beckersDiskCounts(N) == S);
    }
    CHECK(beckersDiskCounts(1) == std::vector<std::uint32_t>{1});
    CHECK(beckersDiskCounts(5) == std::vector<std::uint32_t>{1, 5});
}

TEST_CASE("Beckers hemisphere counts for N = 96 match the published partition") {
    CHECK(beckersHemisphereCounts(96) == std::vector<std::uint32_t>{1, 14, 29, 49, 72, 96});
}

TEST_CASE("Lifted directions are unit, above the plane, and every ring holds its share of pi/N cells") {
    for (std::uint32_t N : {96u, 1000u, 3072u}) {
        const std::vector<float> d = beckersDirections(N);
        REQUIRE(d.size() == 3 * N);
        const std::vector<std::uint32_t> S = beckersDiskCounts(N);
        for (std::uint32_t k = 0; k < N; ++k) {
            const double x = d[3 * k], y = d[3 * k + 1], z = d[3 * k + 2];
            CHECK(x * x + y * y + z * z == doctest::Approx(1.0).epsilon(1e-6));
            CHECK(z > 0.0);
        }
        // Projected radius r^2 = x^2 + y^2: exactly S[j] directions fall inside ring boundary j.
        for (std::size_t j = 0; j < S.size(); ++j) {
            const double boundary = double(S[j]) / N;
            std::uint32_t inside = 0;
            for (std::uint32_t k = 0; k < N; ++k)
                inside += d[3 * k] * d[3 * k] + d[3 * k + 1] * d[3 * k + 1] < boundary;
            CHECK(inside == S[j]);
        }
    }
}
