// Fortran edit descriptors as gfortran writes them (ppohdem10_dem_format.hpp).
#include "ppohdem10_dem_format.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace ppohdem::compat::fortran {
namespace {

std::string right_justify(const std::string& s, int w) {
  const auto width = static_cast<std::size_t>(w);
  if (s.size() > width) return std::string(width, '*');
  return std::string(width - s.size(), ' ') + s;
}

/// The significant digits of |v| correctly rounded to `digits`, and the decimal exponent e of
/// the rounded value (|v| ~ d1.d2d3... x 10^e).
struct Decimal {
  std::string digits;
  int exponent = 0;
};
Decimal decimal_digits(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*e", digits - 1, std::fabs(v));
  const std::string s(buf);
  Decimal out;
  const std::size_t e = s.find('e');
  for (std::size_t k = 0; k < e; ++k) {
    if (s[k] != '.') out.digits += s[k];
  }
  out.exponent = std::atoi(s.c_str() + e + 1);
  return out;
}

std::string exponent_text(int exponent, int min_digits, bool letter_always) {
  char buf[16];
  const int magnitude = std::abs(exponent);
  const char sign = exponent < 0 ? '-' : '+';
  if (!letter_always && magnitude > 99) {
    std::snprintf(buf, sizeof buf, "%c%03d", sign, magnitude);
  } else {
    std::snprintf(buf, sizeof buf, "E%c%0*d", sign, min_digits, magnitude);
  }
  return buf;
}

}  // namespace

std::string e_format(double v, int w, int d) {
  std::string s = std::signbit(v) ? "-" : "";
  if (v == 0.0) {
    s.append("0.").append(static_cast<std::size_t>(d), '0').append("E+00");
    return right_justify(s, w);
  }
  const Decimal dec = decimal_digits(v, d);
  s.append("0.").append(dec.digits).append(exponent_text(dec.exponent + 1, 2, false));
  return right_justify(s, w);
}

std::string es_format(double v, int w, int d) {
  std::string s = std::signbit(v) ? "-" : "";
  if (v == 0.0) {
    s.append("0.").append(static_cast<std::size_t>(d), '0').append("E+00");
    return right_justify(s, w);
  }
  const Decimal dec = decimal_digits(v, d + 1);
  s += dec.digits.substr(0, 1) + "." + dec.digits.substr(1) + exponent_text(dec.exponent, 2, false);
  return right_justify(s, w);
}

std::string f_format(double v, int w, int d) {
  char buf[400];
  std::snprintf(buf, sizeof buf, "%.*f", d, v);
  return right_justify(buf, w);
}

std::string i_format(long v, int w) { return right_justify(std::to_string(v), w); }

std::string list_directed_real(double v) {
  constexpr int kDigits = 17;  // REAL(8)
  const std::string sign = std::signbit(v) ? "-" : "";
  if (v == 0.0) return sign + "0." + std::string(kDigits - 1, '0');  // F form, 16 decimals
  const Decimal dec = decimal_digits(v, kDigits);
  if (dec.exponent >= -1 && dec.exponent < kDigits) {
    // F form with 17 - (e + 1) decimals.
    if (dec.exponent == -1) return sign + "0." + dec.digits;
    const auto integer_digits = static_cast<std::size_t>(dec.exponent + 1);
    return sign + dec.digits.substr(0, integer_digits) + "." + dec.digits.substr(integer_digits);
  }
  char exponent[16];
  std::snprintf(exponent, sizeof exponent, "E%c%03d", dec.exponent < 0 ? '-' : '+', std::abs(dec.exponent));
  return sign + dec.digits.substr(0, 1) + "." + dec.digits.substr(1) + exponent;
}

}  // namespace ppohdem::compat::fortran
