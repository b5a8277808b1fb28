// Clausen's and Lobachevsky's functions, needed for the CETM energy (Springborn et al. 2008, Sec. 4).
#pragma once

namespace bdinterp {

// Cl2(x) = -integral_0^x log|2 sin(t/2)| dt, for any real x (2*pi periodic, odd). Absolute error ~1e-16.
double clausen2(double x);

// Lobachevsky's function L(x) = -integral_0^x log|2 sin t| dt = Cl2(2x) / 2. L(0) = L(pi/2) = L(pi) = 0.
inline double lobachevsky(double x) { return 0.5 * clausen2(2.0 * x); }

}  // namespace bdinterp
