// Unit tests of the NCC kernel, the bilinear sampler it relies on, the 14 patch
// orientations and the photo options (common/photo/).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "common/error.h"
#include "common/image.h"
#include "common/params.h"
#include "common/photo/ncc.h"
#include "common/photo/options.h"
#include "common/photo/orientations.h"

using namespace tetmvs;
using namespace tetmvs::photo;

namespace {
// Deterministic uniform numbers in [0, 1) (xorshift; independent of the standard library).
struct Rng {
  uint64_t s;
  explicit Rng(uint64_t seed) : s(seed * 2654435761ull + 1) {}
  double operator()() {
    s ^= s << 13;
    s ^= s >> 7;
    s ^= s << 17;
    return static_cast<double>(s >> 11) * (1.0 / 9007199254740992.0);
  }
};
std::vector<float> noise(int n, uint64_t seed) {
  Rng r(seed);
  std::vector<float> v(n);
  for (auto& x : v) x = static_cast<float>(r());
  return v;
}
}  // namespace

TEST(Ncc, IdenticalPatchesGiveOne) {
  for (int n : {11, 121}) {
    const auto a = noise(n, 1);
    EXPECT_NEAR(ncc(a.data(), a.data(), n), 1.0f, 1e-6f) << n;
  }
}

TEST(Ncc, GainAndOffsetInvariant) {
  const auto a = noise(121, 2);
  for (auto [g, o] : {std::pair{2.0f, 0.0f}, {0.3f, 0.5f}, {1.0f, -0.7f}, {5.0f, 3.0f}}) {
    std::vector<float> b(a.size());
    for (size_t i = 0; i < a.size(); ++i) b[i] = g * a[i] + o;
    EXPECT_NEAR(ncc(a.data(), b.data(), 121), 1.0f, 1e-5f) << g << " " << o;
  }
  // A negative gain flips the sign.
  std::vector<float> b(a.size());
  for (size_t i = 0; i < a.size(); ++i) b[i] = 0.9f - 0.5f * a[i];
  EXPECT_NEAR(ncc(a.data(), b.data(), 121), -1.0f, 1e-5f);
}

TEST(Ncc, ConstantPatchGivesZeroNotNan) {
  const auto a = noise(11, 3);
  const std::vector<float> c(11, 0.42f), z(11, 0.0f);
  EXPECT_EQ(ncc(a.data(), c.data(), 11), 0.0f);
  EXPECT_EQ(ncc(c.data(), a.data(), 11), 0.0f);
  EXPECT_EQ(ncc(c.data(), c.data(), 11), 0.0f);
  EXPECT_EQ(ncc(z.data(), z.data(), 11), 0.0f);
  // Below min_std counts as constant; above it does not.
  std::vector<float> tiny(11, 0.5f);
  tiny[3] += 1e-4f;  // std ~ 3e-5
  EXPECT_EQ(ncc(a.data(), tiny.data(), 11, 1e-3f), 0.0f);
  EXPECT_NE(ncc(a.data(), tiny.data(), 11, 1e-6f), 0.0f);
  // normalize_patch reports constancy and writes zeros.
  float out[11];
  EXPECT_FALSE(normalize_patch(c.data(), 11, 1e-3f, out));
  for (float x : out) EXPECT_EQ(x, 0.0f);
  EXPECT_TRUE(normalize_patch(a.data(), 11, 1e-3f, out));
  double s = 0, ss = 0;
  for (float x : out) s += x, ss += x * x;
  EXPECT_NEAR(s, 0.0, 1e-5);
  EXPECT_NEAR(ss, 1.0, 1e-5);
}

TEST(Ncc, UncorrelatedNoiseNearZero) {
  // Independent uniform noise: NCC ~ N(0, 1/n). n = 1000: |ncc| < 0.12 is > 3.5 sigma.
  int big = 0;
  double mean = 0;
  for (int t = 0; t < 50; ++t) {
    const auto a = noise(1000, 100 + 2 * t), b = noise(1000, 101 + 2 * t);
    const float x = ncc(a.data(), b.data(), 1000);
    mean += x / 50.0;
    if (std::abs(x) > 0.12f) ++big;
  }
  EXPECT_EQ(big, 0);
  EXPECT_LT(std::abs(mean), 0.03);  // 50 draws: sigma of the mean 0.0045
  // And a correlated mix is in between: b = a + noise of equal variance -> 1/sqrt(2).
  const auto a = noise(1000, 7), e = noise(1000, 8);
  std::vector<float> b(1000);
  for (int i = 0; i < 1000; ++i) b[i] = a[i] + e[i];
  EXPECT_NEAR(ncc(a.data(), b.data(), 1000), 1.0 / std::sqrt(2.0), 0.06);
}

TEST(Ncc, RejectsBadSizes) {
  float a[2] = {0, 1};
  EXPECT_THROW(ncc(a, a, 1), Error);
  EXPECT_THROW(ncc(a, a, 2000), Error);
}

TEST(NccDetrended, RampsVanishTextureSurvives) {
  // Two different pure ramps (a shading gradient seen at two alignments): plain NCC says
  // 1, the de-trended patches are constant (zeros, false).
  for (int rows : {1, 11}) {
    const int mu = 11, n = mu * rows;
    std::vector<float> r1(n), r2(n), t(n), out(n);
    for (int j = 0; j < rows; ++j)
      for (int i = 0; i < mu; ++i) {
        r1[j * mu + i] = 0.2f + 0.01f * i + 0.003f * j;
        r2[j * mu + i] = 0.5f + 0.03f * i + 0.009f * j;
      }
    EXPECT_NEAR(ncc(r1.data(), r2.data(), n), 1.0f, 1e-5f) << rows;
    EXPECT_FALSE(normalize_patch_detrended(r1.data(), mu, rows, 1e-3f, out.data())) << rows;
    for (float x : out) EXPECT_EQ(x, 0.0f);
    // Texture on top of different ramps: the de-trended patches are identical (NCC 1),
    // zero-mean, unit-norm and orthogonal to both ramps.
    const auto tex = noise(n, 42);
    std::vector<float> a(n), b(n), na(n), nb(n);
    for (int q = 0; q < n; ++q) a[q] = r1[q] + 0.05f * tex[q], b[q] = 2.f * (r2[q] + 0.05f * tex[q]) + 0.1f;
    ASSERT_TRUE(normalize_patch_detrended(a.data(), mu, rows, 1e-3f, na.data()));
    ASSERT_TRUE(normalize_patch_detrended(b.data(), mu, rows, 1e-3f, nb.data()));
    double s = 0, ss = 0, m1 = 0, m2 = 0;
    for (int j = 0; j < rows; ++j)
      for (int i = 0; i < mu; ++i) {
        const double x = na[j * mu + i];
        s += x, ss += x * x, m1 += x * (i - 5), m2 += x * (j - rows / 2);
      }
    EXPECT_NEAR(s, 0.0, 1e-5);
    EXPECT_NEAR(ss, 1.0, 1e-5);
    EXPECT_NEAR(m1, 0.0, 1e-4);
    if (rows > 1) {
      EXPECT_NEAR(m2, 0.0, 1e-4);
    }
    EXPECT_NEAR(ncc_normalized(na.data(), nb.data(), n), 1.0f, 1e-4f);
    // Plain NCC of the textured patches is pulled toward the ramps' 1; the de-trended
    // NCC of texture on a ramp with independent texture on a ramp is near 0.
    const auto tex2 = noise(n, 43);
    for (int q = 0; q < n; ++q) b[q] = r2[q] + 0.05f * tex2[q];
    ASSERT_TRUE(normalize_patch_detrended(b.data(), mu, rows, 1e-3f, nb.data()));
    const float plain = ncc(a.data(), b.data(), n), detr = ncc_normalized(na.data(), nb.data(), n);
    EXPECT_GT(plain, 0.8f) << rows;
    EXPECT_LT(std::abs(detr), rows == 1 ? 0.7f : 0.35f) << rows;
    EXPECT_EQ(ramp_norm2(11, rows), static_cast<float>(110 * rows));
  }
}

TEST(PhotoBilinear, ExactOnLinearImages) {
  cv::Mat img(40, 50, CV_32F);
  const auto f = [](double u, double v) { return 0.1 + 0.013 * u - 0.007 * v; };
  for (int v = 0; v < img.rows; ++v)
    for (int u = 0; u < img.cols; ++u) img.at<float>(v, u) = static_cast<float>(f(u, v));
  Rng r(5);
  for (int t = 0; t < 500; ++t) {
    const double u = r() * 49, v = r() * 39;
    float out = -1;
    ASSERT_TRUE(sample_bilinear(img, u, v, out)) << u << " " << v;
    EXPECT_NEAR(out, f(u, v), 2e-6) << u << " " << v;
  }
  // Pixel centres (including the last row/column) are exact.
  float out = 0;
  ASSERT_TRUE(sample_bilinear(img, 49, 39, out));
  EXPECT_FLOAT_EQ(out, img.at<float>(39, 49));
  // Outside the image: refused, output untouched.
  out = -5;
  EXPECT_FALSE(sample_bilinear(img, -0.01, 3, out));
  EXPECT_FALSE(sample_bilinear(img, 49.01, 3, out));
  EXPECT_FALSE(sample_bilinear(img, 3, 39.5, out));
  EXPECT_EQ(out, -5);
}

TEST(PhotoOrientations, FourteenUnitDirectionsClosedUnderNegation) {
  const auto& o = orientations();
  int axes = 0, diags = 0;
  for (int i = 0; i < kNumOrientations; ++i) {
    EXPECT_NEAR(o[i].norm(), 1.0, 1e-12);
    const int nz = (o[i].array().abs() > 1e-9).count();
    axes += nz == 1;
    diags += nz == 3;
    int opposite = 0;
    for (int j = 0; j < kNumOrientations; ++j) {
      if (j != i) {
        EXPECT_LT(o[i].dot(o[j]), 1 - 1e-9) << i << " " << j;
      }
      opposite += o[i].dot(o[j]) < -1 + 1e-9;
    }
    EXPECT_EQ(opposite, 1) << i;
  }
  EXPECT_EQ(axes, 6);
  EXPECT_EQ(diags, 8);
  // Largest angle from any direction to its nearest orientation: 36.2 deg, at
  // (1, sqrt(3) - 1, 0) normalized, equidistant from +x and two diagonals.
  Rng r(9);
  for (int t = 0; t < 2000; ++t) {
    Eigen::Vector3d n(r() - 0.5, r() - 0.5, r() - 0.5);
    if (n.norm() < 1e-3) continue;
    n.normalize();
    const int b = nearest_orientation(n);
    for (int j = 0; j < kNumOrientations; ++j) EXPECT_GE(o[b].dot(n), o[j].dot(n));
    EXPECT_GT(o[b].dot(n), std::cos(36.3 * M_PI / 180));
  }
  EXPECT_EQ(nearest_orientation(Eigen::Vector3d(0.1, 0.2, 1)), 4);
  EXPECT_EQ(nearest_orientation(Eigen::Vector3d(-1, -1.1, -0.9)), 13);
}

TEST(PhotoOrientations, StablePerpendicular) {
  Rng r(11);
  for (int t = 0; t < 200; ++t) {
    const Eigen::Vector3d n = Eigen::Vector3d(r() - 0.5, r() - 0.5, r() - 0.5).normalized();
    const Eigen::Vector3d p = stable_perpendicular(n);
    EXPECT_NEAR(p.norm(), 1.0, 1e-12);
    EXPECT_NEAR(p.dot(n), 0.0, 1e-12);
    EXPECT_EQ(p, stable_perpendicular(n));
  }
  for (int i = 0; i < kNumOrientations; ++i)
    EXPECT_NEAR(stable_perpendicular(orientations()[i]).dot(orientations()[i]), 0.0, 1e-12);
}

TEST(PhotoOptions, DefaultsPassAndBadValuesAreRejected) {
  photo::Options o;
  EXPECT_NO_THROW(o.check());
  EXPECT_EQ(o.k_prime(), 3);
  EXPECT_EQ(o.min_cams(), 4);
  photo::Options k8 = o;
  k8.k = 8;
  EXPECT_EQ(k8.k_prime(), 4);
  const auto bad = [&](auto mutate) {
    photo::Options b = o;
    mutate(b);
    EXPECT_THROW(b.check(), Error);
  };
  bad([](photo::Options& b) { b.mu = 10; });
  bad([](photo::Options& b) { b.mu = 1; });
  bad([](photo::Options& b) { b.mu = kMaxMu + 2; });
  bad([](photo::Options& b) { b.k = 3; });
  bad([](photo::Options& b) { b.k = kMaxK + 1; });
  bad([](photo::Options& b) { b.cone_deg = 0; });
  bad([](photo::Options& b) { b.cone_deg = 90; });
  bad([](photo::Options& b) { b.cone_deg = NAN; });
  bad([](photo::Options& b) { b.T = 1.0; });
  bad([](photo::Options& b) { b.min_std = -1; });
  try {
    photo::Options b = o;
    b.k = 2;
    b.check();
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("k = 2"), std::string::npos) << e.what();
  }
}

TEST(PhotoOptions, FromParamsRejectsWhatTheMeasureCannotUse) {
  Params p = Params::defaults();
  // (that the fields' defaults are defaults.json's values: test_param_binding.cpp)
  // Values the parameter table accepts but the measure cannot use are rejected up front.
  p.set("photo.mu=10");
  EXPECT_THROW(photo::Options::from_params(p), Error);
  p = Params::defaults();
  p.set("photo.k=8");
  p.set("photo.T=0.45");
  EXPECT_EQ(photo::Options::from_params(p).k_prime(), 4);
  EXPECT_EQ(photo::Options::from_params(p).T, 0.45);
}
