// Kernel/host shared structs: sizes and offsets are what the OpenCL side assumes.
#include <gtest/gtest.h>

#include <cstddef>

#include "kernels/shared/luminaire.h"
#include "kernels/shared/surface.h"

static_assert(sizeof(NfSurface) == 64);
static_assert(offsetof(NfSurface, nx) == 16);
static_assert(offsetof(NfSurface, vx) == 32);
static_assert(offsetof(NfSurface, base_r) == 48);
static_assert(sizeof(NfLuminaire) % 4 == 0);
static_assert(offsetof(NfLuminaire, res_x) == 56);
static_assert(sizeof(NfLuminaire) == 80);

TEST(SharedLayout, VisibilityWords) {
  EXPECT_EQ(NF_VIS_WORDS(1), 1);
  EXPECT_EQ(NF_VIS_WORDS(32), 1);
  EXPECT_EQ(NF_VIS_WORDS(33), 2);
  EXPECT_EQ(NF_VIS_WORDS(143), 5);
}
