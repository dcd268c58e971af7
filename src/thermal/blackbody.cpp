// Blackbody fractions by the exponential series (converges fast for z > 2; more terms below).
#include "thermal/blackbody.hpp"

#include <cmath>
#include <limits>

namespace hemirad::thermal {

double blackbodyFraction(double lambdaT) {
    if (!(lambdaT > 0.0)) return 0.0;
    if (std::isinf(lambdaT)) return 1.0;
    const double z = kSecondRadiationConstant / lambdaT;
    constexpr double kPi4 = 97.40909103400243723644;  // pi^4
    if (z < 0.5) {
        // Long wavelengths: the complementary low-z expansion of the integral of x^3/(e^x - 1) from 0
        // to z (Bernoulli series), 1 - (15/pi^4) z^3 (1/3 - z/8 + z^2/60 - z^4/5040 + z^6/272160 - ...).
        const double z2 = z * z;
        const double integral = z * z2 * (1.0 / 3.0 - z / 8.0 + z2 / 60.0 - z2 * z2 / 5040.0 + z2 * z2 * z2 / 272160.0 -
                                          z2 * z2 * z2 * z2 / 13305600.0);
        return 1.0 - 15.0 / kPi4 * integral;
    }
    double sum = 0.0;
    for (int n = 1; n <= 1000; ++n) {
        const double dn = n;
        const double term = std::exp(-dn * z) / dn * (z * z * z + 3.0 * z * z / dn + 6.0 * z / (dn * dn) + 6.0 / (dn * dn * dn));
        sum += term;
        if (term < 1e-17 * sum) break;
    }
    return 15.0 / kPi4 * sum;
}

double bandFraction(double loUm, double hiUm, double T) {
    if (!(T > 0.0)) return 0.0;
    return blackbodyFraction(hiUm * T) - blackbodyFraction(loUm * T);
}

}  // namespace hemirad::thermal
