#pragma once
// Fortran edit descriptors as gfortran 12 writes them, for the original DEM's output files.
// Digits come from printf's %e / %f, which glibc rounds correctly (ties to even on the exact
// binary value), as libgfortran does; a negative zero keeps its sign (gfortran's -fsign-zero
// default).
#include <string>

namespace ppohdem::compat::fortran {

/// Ew.d: right-justified in w columns, mantissa 0.d1d2..dd, exponent E+xx (E+xxx written as
/// +xxx when |exponent| > 99), zero as 0.000000E+00. E.g. E16.6 of 0.249656369 is
/// `    0.249656E+00`.
std::string e_format(double v, int w, int d);
/// ESw.d: one nonzero digit before the point, d after, exponent E+xx. E.g. ES25.17.
std::string es_format(double v, int w, int d);
/// Fw.d: fixed, d decimals, right-justified in w columns (a leading 0 before the point);
/// w asterisks if it does not fit.
std::string f_format(double v, int w, int d);
/// Iw.
std::string i_format(long v, int w);
/// A REAL(8) written with list-directed output (`write(buf, *) x`) and then trimmed of blanks
/// (`trim(adjustl(buf))`): 17 significant digits; F form for 0.1 <= |x| < 1e17, e.g.
/// 4.9831618753839084 and 0.67367042725224469; otherwise E form with a 3-digit exponent,
/// e.g. 9.9534405509978899E-002.
std::string list_directed_real(double v);

}  // namespace ppohdem::compat::fortran
