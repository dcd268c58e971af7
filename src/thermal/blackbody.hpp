// Blackbody fractions: the part of a blackbody's emission below a wavelength, for band models.
#pragma once

namespace hemirad::thermal {

/// Second radiation constant C2 = h c / k, um K (CODATA 2018).
constexpr double kSecondRadiationConstant = 14387.769;

/// F(0 -> lambda T): the fraction of sigma T^4 emitted below wavelength lambda (lambdaT in um K),
/// by the series (15/pi^4) sum_n (e^{-n z}/n)(z^3 + 3 z^2/n + 6 z/n^2 + 6/n^3), z = C2 / (lambda T)
/// (Chang & Rhee 1984; Siegel & Howell). 0 for lambdaT <= 0, 1 for an infinite one; accurate to 1e-14.
double blackbodyFraction(double lambdaT);

/// The fraction of sigma T^4 between wavelengths lo and hi (um; hi may be infinite) at T (K).
double bandFraction(double loUm, double hiUm, double T);

}  // namespace hemirad::thermal
