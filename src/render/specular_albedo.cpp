#include "render/specular_albedo.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace lt {

const float kSpecularAlbedoTable[kSpecularAlbedoNodes * kSpecularAlbedoNodes] = {
#include "render/specular_albedo_table.inc"
};

namespace {

constexpr int kN = kSpecularAlbedoNodes;

const float* const kTable = kSpecularAlbedoTable;

// Table coordinate s in [0, 1] of alpha (that of mu, t = mu^(1/4): DielectricSpecularAlbedo).
float AlphaCoordinate(float alpha) {
  const float r_min = std::sqrt(kMinGgxAlpha);
  const float u = std::clamp((std::sqrt(std::max(alpha, 0.0f)) - r_min) / (1.0f - r_min), 0.0f, 1.0f);
  return std::cbrt(u * u);  // inverse of r = r_min + (1 - r_min) s^1.5
}

void Locate(float x, int* i, float* f) {
  const float s = std::clamp(x, 0.0f, 1.0f) * float(kN - 1);
  *i = std::min(int(s), kN - 2);
  *f = s - float(*i);
}

// E_avg per row: 2 integral E mu dmu with mu = t^4, E linear in t on each cell,
// = 8 integral E(t) t^7 dt, integrated exactly in double.
struct Averages {
  std::array<float, kN> row{};
  Averages() {
    const double h = 1.0 / (kN - 1);
    for (int j = 0; j < kN; ++j) {
      double sum = 0;
      for (int i = 0; i + 1 < kN; ++i) {
        const double a = i * h, b = (i + 1) * h;
        const double ea = kTable[j * kN + i], eb = kTable[j * kN + i + 1];
        const double slope = (eb - ea) / h;
        // integral of (ea + slope (t - a)) t^7 over [a, b].
        const double m7 = (std::pow(b, 8) - std::pow(a, 8)) / 8, m8 = (std::pow(b, 9) - std::pow(a, 9)) / 9;
        sum += (ea - slope * a) * m7 + slope * m8;
      }
      row[j] = float(8 * sum);
    }
  }
};

const Averages& GetAverages() {
  static const Averages averages;
  return averages;
}

}  // namespace

float DielectricSpecularAlbedoNode(int i, int j) { return kTable[j * kN + i]; }

SpecularAlbedoRow::SpecularAlbedoRow(float alpha) { Locate(AlphaCoordinate(alpha), &j, &f); }

float DielectricSpecularAlbedo(float cos_theta, float alpha) {
  return DielectricSpecularAlbedo(cos_theta, SpecularAlbedoRow(alpha));
}

float DielectricSpecularAlbedoAverage(const SpecularAlbedoRow& alpha) {
  const Averages& avg = GetAverages();
  return avg.row[alpha.j] + alpha.f * (avg.row[alpha.j + 1] - avg.row[alpha.j]);
}

float DielectricSpecularAlbedoAverage(float alpha) { return DielectricSpecularAlbedoAverage(SpecularAlbedoRow(alpha)); }

}  // namespace lt
