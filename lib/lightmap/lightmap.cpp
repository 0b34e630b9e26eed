#include "lightmap/lightmap.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

namespace sss {
namespace {

enum Coverage : std::uint8_t { kEmpty = 0, kInside = 1, kPadded = 2 };

// Twice the signed area of (a, b, p): the edge function of a triangle's rasterization.
double edgeFunction(glm::dvec2 a, glm::dvec2 b, glm::dvec2 p) {
  return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
}

// A triangle's texel centres (its corners' texture coordinates uv[0..2]): every (x, y) whose centre
// lies inside it or on its edges, with the barycentric weights of its corners.
template <class Visit>
void forEachTexelIn(const glm::vec2* uv, int size, Visit visit) {
  glm::dvec2 p[3];
  for (int i = 0; i < 3; ++i) p[i] = glm::dvec2(uv[i]) * double(size) - 0.5;
  const double area = edgeFunction(p[0], p[1], p[2]);
  if (std::abs(area) < 1e-12) return;  // no extent in UV: covers no texel centre
  const double slack = 1e-9 * std::abs(area);
  const int x0 = std::max(0, int(std::ceil(std::min({p[0].x, p[1].x, p[2].x}))));
  const int x1 = std::min(size - 1, int(std::floor(std::max({p[0].x, p[1].x, p[2].x}))));
  const int y0 = std::max(0, int(std::ceil(std::min({p[0].y, p[1].y, p[2].y}))));
  const int y1 = std::min(size - 1, int(std::floor(std::max({p[0].y, p[1].y, p[2].y}))));
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      const glm::dvec2 c(x, y);
      const double w0 = edgeFunction(p[1], p[2], c) / area;
      const double w1 = edgeFunction(p[2], p[0], c) / area;
      const double w2 = 1.0 - w0 - w1;
      if (w0 * std::abs(area) < -slack || w1 * std::abs(area) < -slack ||
          w2 * std::abs(area) < -slack) {
        continue;
      }
      visit(std::size_t(y) * size + x, glm::dvec3(w0, w1, w2));
    }
  }
}

// Texel centres strictly inside two of the original triangles: charts that overlap (triangles
// of a valid unwrap meet only at their borders).
std::size_t countOverlaps(const std::vector<glm::vec2>& cornerTexcoords, int size) {
  std::vector<std::uint8_t> hits(std::size_t(size) * size, 0);
  for (std::size_t t = 0; 3 * t < cornerTexcoords.size(); ++t) {
    forEachTexelIn(&cornerTexcoords[3 * t], size, [&](std::size_t i, glm::dvec3 w) {
      if (std::min({w[0], w[1], w[2]}) > 1e-4 && hits[i] < 2) ++hits[i];
    });
  }
  return std::size_t(std::count(hits.begin(), hits.end(), 2));
}

// One round of dilation: each empty texel next to filled ones takes their mean.
std::size_t dilateOnce(Lightmap& map) {
  const int n = map.size;
  const std::vector<std::uint8_t> before = map.coverage;
  std::size_t filled = 0;
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      const std::size_t i = std::size_t(y) * n + x;
      if (before[i] != kEmpty) continue;
      std::size_t neighbours[8];
      int count = 0;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = x + dx, yy = y + dy;
          if (xx < 0 || yy < 0 || xx >= n || yy >= n) continue;
          const std::size_t j = std::size_t(yy) * n + xx;
          if (before[j] != kEmpty) neighbours[count++] = j;
        }
      }
      if (count == 0) continue;
      for (std::vector<glm::vec3>& image : map.images) {
        glm::dvec3 sum(0.0);
        for (int k = 0; k < count; ++k) sum += glm::dvec3(image[neighbours[k]]);
        image[i] = glm::vec3(sum / double(count));
      }
      map.coverage[i] = kPadded;
      ++filled;
    }
  }
  return filled;
}

}  // namespace

Lightmap fillLightmap(const UvRefinement& refinement,
                      std::span<const std::span<const glm::vec3>> fields,
                      const LightmapLayout& layout) {
  const int n = layout.size;
  Lightmap map;
  map.size = n;
  const std::size_t texels = std::size_t(n) * n;
  map.images.assign(fields.size(), std::vector<glm::vec3>(texels, glm::vec3(0.0f)));
  map.coverage.assign(texels, kEmpty);
  for (std::size_t t = 0; t < refinement.triangles.size(); ++t) {
    const glm::uvec3 tri = refinement.triangles[t];
    forEachTexelIn(&refinement.cornerTexcoords[3 * t], n, [&](std::size_t i, glm::dvec3 w) {
      for (std::size_t f = 0; f < fields.size(); ++f) {
        map.images[f][i] =
            glm::vec3(w[0] * glm::dvec3(fields[f][tri[0]]) + w[1] * glm::dvec3(fields[f][tri[1]]) +
                      w[2] * glm::dvec3(fields[f][tri[2]]));
      }
      map.coverage[i] = kInside;
    });
  }
  map.overlappingTexels = countOverlaps(refinement.originalCornerTexcoords, n);
  map.coveredTexels = std::size_t(std::count(map.coverage.begin(), map.coverage.end(), kInside));
  for (int round = 0; round < layout.padding; ++round) map.paddedTexels += dilateOnce(map);
  return map;
}

glm::vec3 sampleBilinear(std::span<const glm::vec3> image, int size, glm::vec2 uv) {
  const double x = std::clamp(double(uv.x) * size - 0.5, 0.0, double(size - 1));
  const double y = std::clamp(double(uv.y) * size - 0.5, 0.0, double(size - 1));
  const int x0 = std::min(int(x), size - 2 < 0 ? 0 : size - 2);
  const int y0 = std::min(int(y), size - 2 < 0 ? 0 : size - 2);
  const int x1 = std::min(x0 + 1, size - 1), y1 = std::min(y0 + 1, size - 1);
  const double fx = x - x0, fy = y - y0;
  const auto at = [&](int xx, int yy) { return glm::dvec3(image[std::size_t(yy) * size + xx]); };
  return glm::vec3((1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x1, y0)) +
                   fy * ((1 - fx) * at(x0, y1) + fx * at(x1, y1)));
}

SeamReport compareSeams(const UvRefinement& refinement, std::span<const glm::vec3> image, int size,
                        int samplesPerEdge) {
  // Each surface edge's sides: (triangle, corner at the edge's start).
  std::unordered_map<std::uint64_t, std::vector<std::pair<std::uint32_t, int>>> sides;
  for (std::uint32_t t = 0; t < refinement.triangles.size(); ++t) {
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t a = refinement.triangles[t][i], b = refinement.triangles[t][(i + 1) % 3];
      sides[a < b ? (std::uint64_t(a) << 32) | b : (std::uint64_t(b) << 32) | a].emplace_back(t, i);
    }
  }
  SeamReport report;
  double sumDiff2 = 0.0, sumMean2 = 0.0;
  std::vector<std::pair<double, double>> samples;  // |difference|, |mean|
  for (const auto& [key, edgeSides] : sides) {
    if (edgeSides.size() != 2) continue;  // a border, or a non-manifold edge
    // Each side's texture coordinates at the edge's lower-numbered vertex, then the other.
    glm::vec2 ends[2][2];
    for (int s = 0; s < 2; ++s) {
      const auto [t, i] = edgeSides[s];
      const glm::vec2 u0 = refinement.cornerTexcoords[3 * t + i];
      const glm::vec2 u1 = refinement.cornerTexcoords[3 * t + (i + 1) % 3];
      const bool forward = refinement.triangles[t][i] < refinement.triangles[t][(i + 1) % 3];
      ends[s][0] = forward ? u0 : u1;
      ends[s][1] = forward ? u1 : u0;
    }
    if (glm::length(ends[0][0] - ends[1][0]) < 1e-6f &&
        glm::length(ends[0][1] - ends[1][1]) < 1e-6f) {
      continue;  // the same place in the map on both sides: not a seam
    }
    ++report.edges;
    for (int k = 0; k < samplesPerEdge; ++k) {
      const float s = (k + 0.5f) / samplesPerEdge;
      const glm::dvec3 a(sampleBilinear(image, size, glm::mix(ends[0][0], ends[0][1], s)));
      const glm::dvec3 b(sampleBilinear(image, size, glm::mix(ends[1][0], ends[1][1], s)));
      sumDiff2 += glm::dot(a - b, a - b);
      sumMean2 += glm::dot(0.5 * (a + b), 0.5 * (a + b));
      samples.emplace_back(glm::length(a - b), glm::length(0.5 * (a + b)));
    }
  }
  if (sumMean2 > 0.0) report.relativeRms = std::sqrt(sumDiff2 / sumMean2);
  // The worst sample against the seams' RMS value: a dark place's difference is not blown up.
  const double rmsMean = samples.empty() ? 0.0 : std::sqrt(sumMean2 / double(samples.size()));
  for (const auto& [difference, mean] : samples) {
    if (rmsMean > 0.0) report.worstRelative = std::max(report.worstRelative, difference / rmsMean);
  }
  return report;
}

}  // namespace sss
