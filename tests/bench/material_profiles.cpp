// Writes the CSV tables behind tests/bench/results/material: every preset x profile with its total
// reflectance and Gaussian fit, the dipole's totals against the half-space albedo (totals.csv), (K,
// error, time) at several tolerances, and sampled profiles 2 pi r^2 R_d(r) (energy per ln r) with
// their fits for charts. Usage: material_profiles OUT_DIR
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "core/atomic_output.h"
#include "core/error.h"
#include "core/tool.h"
#include "material/diffusion_profile.h"
#include "material/gaussian_sum_fit.h"
#include "material/halfspace_albedo.h"
#include "material/profile_factory.h"

int main(int argc, char** argv) {
  return sss::runTool("material_profiles", [&]() {
    if (argc != 2) throw sss::Error("usage: material_profiles OUT_DIR");
    const std::filesystem::path dir = argv[1];
    {
      sss::AtomicOutput out((dir / "fits.csv").string());
      FILE* f = std::fopen(out.tempPath().c_str(), "w");
      if (!f) sss::fail(out.tempPath(), "cannot write");
      std::fprintf(f,
                   "material,profile,tolerance,total_r,total_g,total_b,K,error,"
                   "total_error_before_scaling,fit_ms\n");
      for (const sss::Material& m : sss::materialPresets())
        for (const std::string& kind : sss::listProfiles()) {
          const auto profile = sss::makeProfile(kind, m);
          const glm::dvec3 t = profile->totalReflectance();
          for (double tol : {0.005, 0.01, 0.02, 0.05}) {
            const sss::GaussianSumFit fit = sss::fitGaussians(*profile, tol);
            const glm::dvec3 e = fit.totalErrorBeforeScaling;
            const double worst = std::max({std::abs(e.x), std::abs(e.y), std::abs(e.z)});
            std::fprintf(f, "%s,%s,%g,%.5f,%.5f,%.5f,%zu,%.5f,%.5f,%.2f\n", m.name.c_str(),
                         kind.c_str(), tol, t.x, t.y, t.z, fit.sum.size(), fit.error, worst,
                         fit.fitSeconds * 1e3);
          }
        }
      std::fclose(f);
      out.commit();
    }
    {
      // The classic dipole's total against the Monte Carlo half-space albedo (what beam and
      // burley integrate to), per preset and channel.
      sss::AtomicOutput out((dir / "totals.csv").string());
      FILE* f = std::fopen(out.tempPath().c_str(), "w");
      if (!f) sss::fail(out.tempPath(), "cannot write");
      std::fprintf(f, "material,channel,reduced_albedo,halfspace_albedo,dipole,dipole_error\n");
      for (const sss::Material& m : sss::materialPresets()) {
        const glm::dvec3 dipole = sss::makeProfile("dipole", m)->totalReflectance();
        for (int c = 0; c < 3; ++c) {
          const double truth = sss::halfSpaceDiffuseAlbedo(m.reducedAlbedo()[c], m.eta);
          std::fprintf(f, "%s,%c,%.6f,%.5f,%.5f,%+.4f\n", m.name.c_str(), "RGB"[c],
                       m.reducedAlbedo()[c], truth, dipole[c], dipole[c] / truth - 1.0);
        }
      }
      std::fclose(f);
      out.commit();
    }
    for (const char* name : {"marble", "skin1", "ketchup"}) {
      const sss::Material m = sss::findMaterialPreset(name);
      sss::AtomicOutput out((dir / (std::string("profile_") + name + ".csv")).string());
      FILE* f = std::fopen(out.tempPath().c_str(), "w");
      if (!f) sss::fail(out.tempPath(), "cannot write");
      std::fprintf(f, "r_mm");
      for (const std::string& kind : sss::listProfiles())
        std::fprintf(f, ",%s_r,%s_g,%s_b,%s_fit_r,%s_fit_g,%s_fit_b", kind.c_str(), kind.c_str(),
                     kind.c_str(), kind.c_str(), kind.c_str(), kind.c_str());
      std::fprintf(f, "\n");
      std::vector<std::unique_ptr<sss::DiffusionProfile>> profiles;
      std::vector<sss::GaussianSum> fits;
      for (const std::string& kind : sss::listProfiles()) {
        profiles.push_back(sss::makeProfile(kind, m));
        fits.push_back(sss::fitGaussians(*profiles.back(), 0.01).sum);
      }
      for (int i = 0; i <= 400; ++i) {
        const double r = std::pow(10.0, -3.0 + 5.0 * i / 400.0);  // 1e-3 .. 100 mm
        std::fprintf(f, "%g", r);
        for (std::size_t p = 0; p < profiles.size(); ++p) {
          // Energy per unit ln r: 2 pi r^2 R_d(r), so that areas on a log axis are energy.
          const double w = 2.0 * M_PI * r * r;
          const glm::dvec3 v = w * profiles[p]->evaluate(r), g = w * fits[p].evaluate(r);
          std::fprintf(f, ",%g,%g,%g,%g,%g,%g", v.x, v.y, v.z, g.x, g.y, g.z);
        }
        std::fprintf(f, "\n");
      }
      std::fclose(f);
      out.commit();
    }
    return 0;
  });
}
