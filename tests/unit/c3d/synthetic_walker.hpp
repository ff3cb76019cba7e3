#pragma once
/// A synthetic Plug-in Gait subject walking along +X (file units mm, Z up), with known joint
/// centres, for gap / trimming / override tests.

#include <cmath>
#include <functional>
#include <map>
#include <string>

#include "c3d_test_writer.hpp"
#include "retarget/core/types.hpp"

namespace rt::test {

struct Walker {
  double fps = 100;
  int frames = 300;
  int absent_leading = 20;  ///< frames before the subject enters (all samples invalid)
  std::string prefix = "Matt:";

  double t(int f) const { return f / fps; }
  double x(int f) const { return 1200.0 * t(f) - 600.0; }
  double bob(int f) const { return 20.0 * std::sin(2 * M_PI * 2 * t(f)); }
  double swing(int f, int side) const { return 40.0 * std::sin(2 * M_PI * t(f) + (side ? M_PI : 0.0)); }

  /// Marker positions [mm] at frame f (side 0 = left: +Y).
  std::map<std::string, Vec3> markers(int f) const {
    std::map<std::string, Vec3> m;
    const Vec3 p(x(f), 0, 950 + bob(f));
    m["LASI"] = p + Vec3(60, 115, 40);
    m["RASI"] = p + Vec3(60, -115, 40);
    m["LPSI"] = p + Vec3(-100, 45, 40);
    m["RPSI"] = p + Vec3(-100, -45, 40);
    for (int s = 0; s < 2; ++s) {
      const double y = s == 0 ? 1 : -1;
      const std::string l = s == 0 ? "L" : "R";
      const double k = x(f) + 10 + swing(f, s);
      m[l + "KNE"] = Vec3(k, y * 150, 500 + bob(f) / 2);
      m[l + "KNM"] = Vec3(k, y * 50, 500 + bob(f) / 2);
      const double a = x(f) + 2 * swing(f, s);
      m[l + "ANK"] = Vec3(a, y * 140, 80);
      m[l + "MED"] = Vec3(a, y * 60, 80);
      m[l + "TOE"] = Vec3(a + 150, y * 100, 40);
      m[l + "HEE"] = Vec3(a - 60, y * 100, 40);
      m[l + "SHO"] = p + Vec3(0, y * 190, 500);
      m[l + "ELB"] = p + Vec3(0, y * 230, 200);
      m[l + "WRA"] = p + Vec3(25, y * 210, -50);
      m[l + "WRB"] = p + Vec3(-25, y * 210, -50);
      m[l + "FIN"] = p + Vec3(0, y * 215, -130);
      m[l + "FHD"] = p + Vec3(80, y * 70, 700);
      m[l + "BHD"] = p + Vec3(-80, y * 70, 700);
    }
    m["C7"] = p + Vec3(-80, 0, 550);
    m["CLAV"] = p + Vec3(60, 0, 500);
    m["T10"] = p + Vec3(-110, 0, 300);
    m["STRN"] = p + Vec3(80, 0, 300);
    return m;
  }

  /// True joint centres [mm] for the markers above.
  Vec3 knee(int f, int s) const { return 0.5 * (markers(f)[(s ? "RKNE" : "LKNE")] + markers(f)[(s ? "RKNM" : "LKNM")]); }
  Vec3 ankle(int f, int s) const { return 0.5 * (markers(f)[(s ? "RANK" : "LANK")] + markers(f)[(s ? "RMED" : "LMED")]); }
  /// Harrington 2007 with PW = 230 mm, PD = 160 mm, pelvis frame aligned with the world.
  Vec3 hip(int f, int s) const {
    const Vec3 p(x(f), 0, 950 + bob(f));
    const double lateral = 0.33 * 230 + 7.3;
    return p + Vec3(60 - 0.24 * 160 - 9.9, s ? -lateral : lateral, 40 - 0.30 * 230 - 10.9);
  }

  /// `invalid(name, frame)` marks extra missing samples.
  C3dSpec spec(const std::function<bool(const std::string&, int)>& invalid = nullptr) const {
    C3dSpec s;
    s.rate = fps;
    const auto names = markers(0);
    for (const auto& [name, p] : names) s.labels.push_back(prefix + name);
    for (int f = 0; f < frames; ++f) {
      std::vector<std::array<float, 4>> row;
      for (const auto& [name, p] : markers(f)) {
        const bool missing = f < absent_leading || (invalid && invalid(name, f));
        row.push_back({static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()), missing ? -1.0f : 0.5f});
      }
      s.samples.push_back(row);
    }
    return s;
  }
};

}  // namespace rt::test
