// Test helper: a square plate as OptiStruct bulk data (free format, SI), n × n CQUAD4 in z = 0
// over [0, a]², every element on SURF 2 of an EDEM card, edges clamped (SPC1 set 1) or free.
#pragma once

#include <string>

#include <fmt/format.h>

namespace quarry::fsi::testing {

struct PlateCards {
  int divisions = 4;
  double side = 0.06;           // a (m)
  double thickness = 0.001;     // t (m)
  double youngs_modulus = 2.1e11;  // Pa
  double poisson_ratio = 0.3;
  double density = 7850.0;      // kg/m³
  bool clamped = true;
};

// A Nastran real: always with a decimal point and an exponent, all digits of the double.
inline std::string bulk_real(double x) { return fmt::format("{:.16E}", x); }

inline std::string plate_bulk_data(const PlateCards& p) {
  const int n = p.divisions;
  std::string text = "BEGIN BULK\nDTI,UNITS,1,KG,N,M,S\n";
  const auto grid = [n](int i, int j) { return j * (n + 1) + i + 1; };
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      text += fmt::format("GRID,{},,{},{},0.\n", grid(i, j), bulk_real(p.side * i / n), bulk_real(p.side * j / n));
  int element = 0;
  std::string surface = "SURF,2,ELFACE\n";
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      ++element;
      text += fmt::format("CQUAD4,{},1,{},{},{},{}\n", element, grid(i, j), grid(i + 1, j), grid(i + 1, j + 1),
                          grid(i, j + 1));
      surface += fmt::format(",{}\n", element);
    }
  text += surface;
  text += fmt::format("PSHELL,1,1,{},1,,1\n", bulk_real(p.thickness));
  text += fmt::format("MAT1,1,{},,{},{}\n", bulk_real(p.youngs_modulus), bulk_real(p.poisson_ratio),
                      bulk_real(p.density));
  if (p.clamped)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i)
        if (i == 0 || j == 0 || i == n || j == n) text += fmt::format("SPC1,1,123456,{}\n", grid(i, j));
  text += "EDEM,100,CONTROL,,,COUPLING,SURF,2,plate\nENDDATA\n";
  return text;
}

}  // namespace quarry::fsi::testing
