// Kernel/host shared structs: sizes and offsets are what the OpenCL side assumes.
#include <gtest/gtest.h>

#include <cstddef>

#include "kernels/shared/kurt.h"
#include "kernels/shared/luminaire.h"
#include "kernels/shared/surface.h"

static_assert(sizeof(NfSurface) == 64);
static_assert(offsetof(NfSurface, nx) == 16);
static_assert(offsetof(NfSurface, vx) == 32);
static_assert(offsetof(NfSurface, base_r) == 48);
static_assert(sizeof(NfLuminaire) % 4 == 0);
static_assert(offsetof(NfLuminaire, res_x) == 56);
static_assert(sizeof(NfLuminaire) == 80);
static_assert(sizeof(NfKurtLobe) == 32);
static_assert(offsetof(NfKurtMaterial, count) == 12);
static_assert(offsetof(NfKurtMaterial, tx) == 16);
static_assert(offsetof(NfKurtMaterial, lobe) == 32);
static_assert(sizeof(NfKurtMaterial) == 160);
static_assert(NF_BRDF_KURT != NF_BRDF_LAMBERT && NF_BRDF_KURT != NF_BRDF_GGX && NF_BRDF_KURT != NF_BRDF_IRRADIANCE &&
              NF_BRDF_KURT != NF_BRDF_SCALAR);

TEST(SharedLayout, VisibilityWords) {
  EXPECT_EQ(NF_VIS_WORDS(1), 1);
  EXPECT_EQ(NF_VIS_WORDS(32), 1);
  EXPECT_EQ(NF_VIS_WORDS(33), 2);
  EXPECT_EQ(NF_VIS_WORDS(143), 5);
}
