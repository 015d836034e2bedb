#pragma once
// Clusters split by normal (docs/indirect.md "Clusters split by normal"): N_v VSGLs of a
// luminaire instance shared among the normal classes of its RSM texels.
#include <vector>

namespace nf::render {

// The VSGL count of each class for N_v = n VSGLs and the classes' PDF masses T_c (the luminance
// power sum P of their texels): n T_c / T rounded by largest remainder (ties: the lower class), then
// every class with T_c > 0 that got none takes one from the class with the most (while that one
// keeps at least one), so that no class's light is dropped when n is at least the number of lit
// classes. Negative or non-finite masses count as 0; with no mass at all every VSGL goes to class
// 0 (they come out empty). The counts add up to n.
std::vector<int> vsgl_class_counts(const std::vector<double>& totals, int n);

}  // namespace nf::render
