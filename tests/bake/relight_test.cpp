// Relightable bakes (lib/bake/relight.h): linearity in the environment, a turned environment
// against a fresh bake under it, the bake's own environment against itself, the file's round
// trip and its refusals.
#include "bake/relight.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <vector>

#include <glm/geometric.hpp>

#include "bake/bake.h"
#include "core/error.h"
#include "core/relative_rms.h"
#include "envmap/environment.h"
#include "image/image.h"
#include "mesh/baked_glb.h"
#include "mesh/baked_ply.h"
#include "mesh/primitives.h"
#include "support/tool_test.h"
#include "transport/interreflection.h"

namespace sss {
namespace {

// `m` as an ASCII PLY without normals.
void writeAsciiPly(const std::string& path, const TriangleMesh& m) {
  std::ofstream out(path);
  out << "ply\nformat ascii 1.0\nelement vertex " << m.positions.size()
      << "\nproperty float x\nproperty float y\nproperty float z\nelement face "
      << m.triangles.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const glm::vec3& p : m.positions) out << p.x << ' ' << p.y << ' ' << p.z << '\n';
  for (const glm::uvec3& t : m.triangles) out << "3 " << t.x << ' ' << t.y << ' ' << t.z << '\n';
}

// A bumpy sphere, 20 mm across, with concave valleys between its bumps (it shadows itself).
void writeBumpySphere(const std::string& path) {
  TriangleMesh m = makeIcosphere(3, 1.0f);
  for (glm::vec3& p : m.positions)
    p *= 10.0f *
         (1.0f + 0.3f * std::sin(4.0f * p.x) * std::sin(4.0f * p.y + 1.0f) * std::cos(3.0f * p.z));
  writeAsciiPly(path, m);
}

BakeSettings settingsFor(const std::string& mesh, const std::string& sky, double rotateDeg = 0.0) {
  BakeSettings s;
  s.meshPath = mesh;
  s.environment = sky;
  s.orientation.rotateDeg = rotateDeg;
  s.material = findMaterialPreset("marble");
  s.mmPerUnit = 1.0;
  s.run = {.seed = 3, .threads = 2, .quiet = true};
  // The stages traced per environment ride on the ratio g (relight.h): off, so that the stored
  // transfer itself is what is compared.
  s.farField = FarFieldMode::Off;
  s.unscattered = UnscatteredMode::Off;
  return s;
}

// A smooth environment: no compact light in it.
Cubemap gradient(const glm::vec3& axis, const glm::vec3& colour) {
  Cubemap map(32);
  forEachTexel(32, [&](int f, int x, int y) {
    map.at(f, x, y) = colour * (1.2f + glm::dot(map.direction(f, x, y), axis));
  });
  return map;
}

class Relight : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::filesystem::temp_directory_path() /
           ("sss-test-" + std::to_string(::getpid()) + "-relight");
    std::filesystem::create_directories(dir_);
    mesh_ = file("bumpy.ply");
    writeBumpySphere(mesh_);
    BakeSettings s = settingsFor(mesh_, kSky);
    s.relightOrder = 3;
    out_ = new BakeOutput(bake(s));
    transfer_ = new RelightTransfer(relightTransferOf(out_->baked));
    material_ = new Material(findMaterialPreset("marble"));
  }
  static void TearDownTestSuite() {
    delete transfer_;
    delete out_;
    delete material_;
    std::error_code ignored;
    std::filesystem::remove_all(dir_, ignored);
  }
  static std::string file(const std::string& name) { return (dir_ / name).string(); }
  static RelightableMesh bakeMesh() { return {out_->baked.mesh, *material_, *transfer_}; }
  static RelitLight relit(const Cubemap& env) {
    return relight("bumpy.ply", bakeMesh(), env, {.seed = 3, .threads = 2, .quiet = true});
  }

  static constexpr const char* kSky = "sky:elevation=35,azimuth=60,turbidity=3";
  static std::filesystem::path dir_;
  static std::string mesh_;
  static BakeOutput* out_;
  static RelightTransfer* transfer_;
  static Material* material_;
};
std::filesystem::path Relight::dir_;
std::string Relight::mesh_;
BakeOutput* Relight::out_ = nullptr;
RelightTransfer* Relight::transfer_ = nullptr;
Material* Relight::material_ = nullptr;

TEST_F(Relight, StoresTheTransferAndReportsItsOwnEnvironment) {
  const BakedMesh& b = out_->baked;
  EXPECT_EQ(b.relightOrder, 3);
  EXPECT_EQ(b.relightTransfer.size(), 16 * b.mesh.vertexCount());
  EXPECT_EQ(b.radianceGain.size(), b.mesh.vertexCount());
  EXPECT_FALSE(b.relightTransport.empty());
  const RelightReport& r = out_->report.relight;
  EXPECT_GT(r.blockedFraction, 0.01);  // the valleys shadow
  EXPECT_EQ(r.compactLights, 1);       // the sky's sun
  // Relit under its own environment, against itself: what the report says, and small.
  const RelitLight own = relit(loadBakeEnvironment(settingsFor(mesh_, kSky)).radiance);
  EXPECT_NEAR(relativeRms(own.radianceNormal, b.radianceNormal), r.selfError, 1e-6);
  EXPECT_FALSE(own.unscattered.traced);  // marble, and the bake's stage off
  EXPECT_EQ(own.unscattered.reason, "not traced by the bake");
  EXPECT_LT(r.selfError, 0.03);
  EXPECT_GT(r.selfError, 0.0);
}

TEST_F(Relight, IsLinearInTheEnvironment) {
  const Cubemap a = gradient(glm::vec3(0.0f, 1.0f, 0.0f), glm::vec3(1.0f, 0.9f, 0.8f));
  const Cubemap b =
      gradient(glm::normalize(glm::vec3(1.0f, -0.5f, 0.2f)), glm::vec3(0.3f, 0.5f, 0.9f));
  Cubemap sum = a;
  forEachTexel(32, [&](int f, int x, int y) { sum.at(f, x, y) += b.at(f, x, y); });
  const RelitLight ra = relit(a), rb = relit(b), rsum = relit(sum);
  EXPECT_EQ(rsum.compactLights, 0);
  std::vector<glm::vec3> added = ra.radianceNormal;
  for (std::size_t v = 0; v < added.size(); ++v) added[v] += rb.radianceNormal[v];
  // The bounces' sums run at a tolerance: linear to well within it.
  EXPECT_LT(relativeRms(rsum.radianceNormal, added), 2e-3);
  // And a sun beside a sky: the sun alone is a compact light, as it is in the sum.
  const Cubemap sun = loadBakeEnvironment(settingsFor(mesh_, kSky)).radiance;
  Cubemap sunAndSky = sun;
  forEachTexel(sun.size(), [&](int f, int x, int y) {
    sunAndSky.at(f, x, y) += a.sample(sun.direction(f, x, y));
  });
  Cubemap aFine(sun.size());
  forEachTexel(sun.size(),
               [&](int f, int x, int y) { aFine.at(f, x, y) = a.sample(sun.direction(f, x, y)); });
  const RelitLight rs = relit(sun), ra2 = relit(aFine), rboth = relit(sunAndSky);
  std::vector<glm::vec3> both = rs.radianceNormal;
  for (std::size_t v = 0; v < both.size(); ++v) both[v] += ra2.radianceNormal[v];
  EXPECT_LT(relativeRms(rboth.radianceNormal, both), 0.01);
}

// One session for several environments (sss-render's light turntable): each relight is what a
// relight of its own gives, bit for bit, in any order, the same environment twice included. The
// fixture's bake has bounces, so the gather's rays (traced once) and its swapped sky count.
TEST_F(Relight, ASessionRelightsEachEnvironmentAsARelightOfItsOwn) {
  std::vector<std::string> key{""};  // method,tolerance,...,entry,bounces,rays (relight.h)
  for (const char c : transfer_->relightTransport) c == ',' ? key.emplace_back() : key.back() += c;
  ASSERT_EQ(key.size(), 10u);
  ASSERT_NE(key[8], "0");  // bounces
  const Cubemap sun = loadBakeEnvironment(settingsFor(mesh_, kSky)).radiance;
  const Cubemap turned = loadBakeEnvironment(settingsFor(mesh_, kSky, 120.0)).radiance;
  const Cubemap sky = gradient(glm::vec3(0.0f, 0.0f, 1.0f), glm::vec3(0.4f, 0.6f, 0.9f));
  RelightSession session("bumpy.ply", bakeMesh(), {.seed = 3, .threads = 2, .quiet = true});
  for (const Cubemap* env : {&sun, &turned, &sky, &sun}) {
    const RelitLight fromSession = session.relight(*env), own = relit(*env);
    EXPECT_EQ(fromSession.radianceNormal, own.radianceNormal);
    EXPECT_EQ(fromSession.exitance, own.exitance);
    EXPECT_EQ(fromSession.compactLights, own.compactLights);
  }
}

// What sss-render's vertex shader relights from (RelitSplit): the smooth light's SH summed against
// the transfer, plus the rest (the compact lights and the bounces), clamped at zero, times g b, is
// relight()'s exitance up to float rounding. Without bounces, a smooth light leaves no rest: no
// per-vertex work before drawing.
TEST_F(Relight, ItsSplitAddsUpToTheRelight) {
  const Cubemap sun = loadBakeEnvironment(settingsFor(mesh_, kSky, 75.0)).radiance;
  const Cubemap sky = gradient(glm::vec3(0.3f, 0.8f, 0.1f), glm::vec3(0.9f, 0.6f, 0.4f));
  RelightTransfer noBounces = *transfer_;
  noBounces.gatherFrontHits.clear();
  std::vector<std::string> key{""};
  for (const char c : noBounces.relightTransport) c == ',' ? key.emplace_back() : key.back() += c;
  ASSERT_EQ(key.size(), 10u);
  key[8] = "0";
  noBounces.relightTransport = key[0];
  for (std::size_t i = 1; i < key.size(); ++i) noBounces.relightTransport += "," + key[i];
  const RunContext run{.seed = 3, .threads = 2, .quiet = true};
  for (const RelightTransfer* t : {transfer_, &noBounces}) {
    const RelightableMesh mesh{out_->baked.mesh, *material_, *t};
    RelightSession session("bumpy.ply", mesh, run);
    for (const Cubemap* env : {&sun, &sky}) {
      const RelitLight whole = session.relight(*env);
      const RelitSplit split = session.relightSplit(*env);
      EXPECT_EQ(split.compactLights, whole.compactLights);
      const bool rest = t == transfer_ || env == &sun;
      ASSERT_EQ(split.restExitance.size(), rest ? whole.exitance.size() : 0u);
      std::vector<glm::vec3> b =
          transferredExitance(t->relightTransfer, t->order, split.smoothLight);
      for (std::size_t v = 0; v < b.size(); ++v) {
        if (rest) b[v] += split.restExitance[v];
        b[v] = glm::max(b[v], glm::vec3(0.0f)) * t->radianceGain[v] * t->exitancePerRadiance[v];
      }
      EXPECT_LT(relativeRms(b, whole.exitance), 1e-5);
      EXPECT_GT(relativeRms(whole.exitance, out_->baked.exitance), 0.05);  // relit, not as baked
    }
  }
}

// The bake stores which of its gather's rays met the object (the fixture's bake has bounces), so
// that a relight traces only those: the same light, bit for bit, as tracing them all.
TEST_F(Relight, StoredFrontHitsRelightAsTracingEveryRay) {
  const std::size_t n = out_->baked.mesh.positions.size();
  ASSERT_EQ(transfer_->gatherFrontHits.size(), n * frontHitWords(64));
  RelightTransfer traced = *transfer_;
  traced.gatherFrontHits.clear();
  const Cubemap sun = loadBakeEnvironment(settingsFor(mesh_, kSky, 30.0)).radiance;
  const RunContext run{.seed = 3, .threads = 2, .quiet = true};
  const RelitLight stored = relit(sun);
  const RelitLight all = relight("bumpy.ply", {out_->baked.mesh, *material_, traced}, sun, run);
  EXPECT_EQ(stored.radianceNormal, all.radianceNormal);
  EXPECT_EQ(stored.exitance, all.exitance);
  // A stored mask that does not fit the stored gather is refused, naming the file.
  RelightTransfer shortMask = *transfer_;
  shortMask.gatherFrontHits.resize(shortMask.gatherFrontHits.size() - 4);
  try {
    relight("bumpy.ply", {out_->baked.mesh, *material_, shortMask}, sun, run);
    ADD_FAILURE() << "a short mask";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("bumpy.ply: gather_hits:"), std::string::npos) << e.what();
  }
}

TEST_F(Relight, SameResultForAnyThreadCount) {
  const Cubemap sky = loadBakeEnvironment(settingsFor(mesh_, kSky, 45.0)).radiance;
  const RelitLight one = relight("bumpy.ply", bakeMesh(), sky, {.seed = 3, .threads = 1});
  const RelitLight two = relight("bumpy.ply", bakeMesh(), sky, {.seed = 3, .threads = 2});
  EXPECT_EQ(one.radianceNormal, two.radianceNormal);
  EXPECT_EQ(one.exitance, two.exitance);
  BakeSettings s = settingsFor(mesh_, kSky);
  s.relightOrder = 1;
  s.run.threads = 1;
  const BakeOutput single = bake(s);
  s.run.threads = 2;
  const BakeOutput dual = bake(s);
  EXPECT_EQ(single.baked.relightTransfer, dual.baked.relightTransfer);
  EXPECT_EQ(single.baked.radianceGain, dual.baked.radianceGain);
}

TEST_F(Relight, ATurnedEnvironmentMatchesAFreshBakeUnderIt) {
  for (double rotate : {90.0, 200.0}) {
    const BakeSettings s = settingsFor(mesh_, kSky, rotate);
    const BakeOutput fresh = bake(s);
    const RelitLight r = relit(loadBakeEnvironment(s).radiance);
    // Under the unturned sky the transfer's own error is selfError; turned, it stays of that order.
    EXPECT_LT(relativeRms(r.radianceNormal, fresh.baked.radianceNormal), 0.04) << rotate;
    // Not the unturned bake: the turn matters.
    EXPECT_GT(relativeRms(out_->baked.radianceNormal, fresh.baked.radianceNormal), 0.1) << rotate;
  }
}

// A 10 mm ketchup sphere under a sun lets part of the sun through unscattered onto its far side
// (unscattered_light.h). That light leaves along the sun's direction, which a ratio per vertex
// cannot turn with the light: the relight traces it again for the turned sun.
TEST(RelightUnscattered, TheLightThatCrossesFollowsATurnedSun) {
  const test::ScratchDir dir;
  const std::string mesh = dir.path("sphere.ply");
  writeAsciiPly(mesh, makeIcosphere(3, 5.0f));
  const auto settings = [&](double rotateDeg, UnscatteredMode unscattered) {
    BakeSettings s = settingsFor(mesh, "sky:elevation=10,azimuth=0,turbidity=3", rotateDeg);
    s.material = findMaterialPreset("ketchup");
    s.unscattered = unscattered;
    s.tolerance = 0.05;  // the unscattered light's paths to a budget of 1.5 %: quick
    return s;
  };
  BakeSettings s = settings(0.0, UnscatteredMode::On);
  s.relightOrder = 3;
  const BakeOutput relightable = bake(s);
  ASSERT_NE(relightable.baked.relightTransport.find(",unscattered"), std::string::npos);
  const Material ketchup = findMaterialPreset("ketchup");
  const RelightTransfer transfer = relightTransferOf(relightable.baked);
  const RelightableMesh relightableMesh{relightable.baked.mesh, ketchup, transfer};
  const BakeSettings turned = settings(150.0, UnscatteredMode::On);
  const BakeOutput fresh = bake(turned);
  const RelitLight r = relight("sphere.ply", relightableMesh, loadBakeEnvironment(turned).radiance,
                               {.seed = 3, .threads = 2, .quiet = true});
  EXPECT_TRUE(r.unscattered.traced) << r.unscattered.reason;
  const double error = relativeRms(r.radianceNormal, fresh.baked.radianceNormal);
  // The unscattered light matters here: without it the fresh bake is much darker in places.
  const BakeOutput without = bake(settings(150.0, UnscatteredMode::Off));
  const double unscattered = relativeRms(without.baked.radianceNormal, fresh.baked.radianceNormal);
  EXPECT_GT(unscattered, 0.05);
  EXPECT_LT(error, 0.3 * unscattered);
  // B holds the scattered light alone, as a fresh bake's does.
  EXPECT_LT(relativeRms(r.exitance, fresh.baked.exitance), 0.5 * error + 0.01);
}

// A gradient lies in bands 0 and 1 (no truncation, no compact light), and its band-1 light takes
// both signs over the object: relit, it is what a fresh bake under the same map gives, to within
// the transfer's rays and the sums' tolerance.
TEST_F(Relight, ALightOfBothSignsPerBasisFunctionMatchesAFreshBake) {
  const Cubemap sky =
      gradient(glm::normalize(glm::vec3(0.6f, -0.3f, 0.74f)), glm::vec3(0.5f, 0.7f, 1.0f));
  const std::string path = file("gradient.exr");
  writeImage(path, cubemapToStack(sky));
  const BakeOutput fresh = bake(settingsFor(mesh_, path));
  const RelitLight r = relit(loadBakeEnvironment(settingsFor(mesh_, path)).radiance);
  EXPECT_EQ(r.compactLights, 0);
  EXPECT_LT(relativeRms(r.radianceNormal, fresh.baked.radianceNormal), 0.01);
  // Not the bake's own light: the gradient is what is relit.
  EXPECT_GT(relativeRms(out_->baked.radianceNormal, fresh.baked.radianceNormal), 0.2);
}

// A file read back holds the relightable bake's values bit-exactly.
void expectSameTransfer(const BakedPlyContents& read, const BakedMesh& baked) {
  ASSERT_TRUE(read.hasRelight);
  EXPECT_EQ(read.baked.relightOrder, baked.relightOrder);
  EXPECT_EQ(read.baked.relightTransfer, baked.relightTransfer);
  EXPECT_EQ(read.baked.radianceGain, baked.radianceGain);
  EXPECT_EQ(read.baked.exitancePerRadiance, baked.exitancePerRadiance);
  EXPECT_EQ(read.baked.escapeProbability, baked.escapeProbability);
  EXPECT_EQ(read.baked.gatherFrontHits, baked.gatherFrontHits);
  EXPECT_EQ(read.baked.relightTransport, baked.relightTransport);
}

TEST_F(Relight, RoundTripsThroughThePlyAndTheGlb) {
  writeBakedPly(file("relightable.ply"), out_->baked);
  expectSameTransfer(readBakedPly(file("relightable.ply")), out_->baked);
  writeBakedGlb(file("relightable.glb"), out_->baked);
  expectSameTransfer(readBakedGlb(file("relightable.glb")), out_->baked);
}

// The header of the relightable PLY with `from` replaced by `to`.
std::string edited(const std::string& bytes, const std::string& from, const std::string& to) {
  std::string out = bytes;
  const std::size_t at = out.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) out.replace(at, from.size(), to);
  return out;
}

TEST_F(Relight, RefusesBrokenFiles) {
  const std::string path = file("good.ply");
  writeBakedPly(path, out_->baked);
  const std::string bytes = test::readFile(path);
  const std::string order = "relight_order=3";
  const std::string key = "relight_transport=" + out_->baked.relightTransport;
  const struct {
    std::string from, to, message;
  } cases[] = {
      {order, "relight_order=9", "relight_order without transfer16_r/g/b"},
      {order, "relight_order=x", "bad 'comment sss relight_order=x'"},
      {order, "relight_orderz=3", "bad 'comment sss relight_transport="},
      {"property short transfer15_b", "property short transfer15_q", "transfer15_r/g/b"},
      {"property float transfer_scale_g", "property float transfer_scale_q",
       "transfer_scale_r/g/b"},
      {key, "relight_transport=a b", "bad"},
      {"property ushort gather_hits_3", "property ushort gather_hitsX3",
       "gather_hits: 3 words per vertex, not whole groups of four"},
  };
  for (const auto& c : cases) {
    const std::string bad = file("bad.ply");
    test::writeText(bad, edited(bytes, c.from, c.to));
    try {
      readBakedPly(bad);
      ADD_FAILURE() << c.to;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(c.message), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("bad.ply"), std::string::npos) << e.what();
    }
  }
  // A GLB whose extras declare more coefficients than its attributes hold, and one missing a
  // packed attribute.
  writeBakedGlb(file("good.glb"), out_->baked);
  const std::string good = test::readFile(file("good.glb"));
  // The accessor an attribute names in the GLB's JSON ("NAME":index), to point another at it.
  const auto attribute = [&](const std::string& name) {
    const std::size_t at = good.find("\"" + name + "\":");
    EXPECT_NE(at, std::string::npos) << name;
    const std::size_t from = at + name.size() + 3;
    return good.substr(at, good.find_first_not_of("0123456789", from) - at);
  };
  // The gather's hits read from a SHORT accessor (the transfer's last packed steps; a same-length
  // edit: both indices have two digits).
  const std::string hits = attribute("_GATHER_HITS_0"), steps = attribute("_TRANSFER_LOW_11");
  const std::string hitsOnSteps = "\"_GATHER_HITS_0\":" + steps.substr(steps.rfind(':') + 1);
  ASSERT_EQ(hits.size(), hitsOnSteps.size());
  const std::pair<std::string, std::string> glbCases[] = {
      {edited(good, hits, hitsOnSteps), "bad.glb: glTF: _GATHER_HITS_0 is not UNSIGNED_SHORT"},
      {edited(good, "\"order\":3", "\"order\":4"),
       "bad.glb: glTF: a relightable bake of order above 3 without _TRANSFER_EXPONENT_HIGH"},
      {edited(good, "\"_TRANSFER_LOW_11\"", "\"_TRANSFER_LOW_X1\""),
       "bad.glb: glTF: a relightable bake without _TRANSFER_LOW_11"},
  };
  for (const auto& [bytes, message] : glbCases) {
    test::writeText(file("bad.glb"), bytes);
    try {
      readBakedGlb(file("bad.glb"));
      ADD_FAILURE() << message;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  }
  // A transport key that does not parse is refused when relighting.
  RelightTransfer broken = *transfer_;
  broken.relightTransport = "hierarchical,0.01";
  EXPECT_THROW(relight("x.ply", {out_->baked.mesh, *material_, broken},
                       gradient(glm::vec3(0, 1, 0), glm::vec3(1)), {}),
               Error);
  // Nor do its bounces' tail mark ('+') and its gather's visibility set (':N') other than as
  // written: the fields before the bounces kept, the bounces and rays fields replaced.
  std::string head = transfer_->relightTransport;
  for (int field = 0; field < 2; ++field) head.resize(head.rfind(','));
  for (const std::string tail : {"+,64", "3++,64", "3+x,64", "3,64:", "3,64:x", "3,64:-1",
                                 "3,64:5000", "3,64:8:8", "3,:8"}) {
    broken.relightTransport = head + "," + tail;
    try {
      relight("x.ply", {out_->baked.mesh, *material_, broken},
              gradient(glm::vec3(0, 1, 0), glm::vec3(1)), {});
      ADD_FAILURE() << broken.relightTransport;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("bad relight_transport"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace sss
