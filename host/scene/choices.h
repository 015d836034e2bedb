#pragma once
// The enumerations of the choice settings (docs/settings.md) and their names: one table per enum.
// Each table is the one binding between a setting's text ("halton-scrambled") and its typed value
// (SamplerKind::halton_scrambled): the registry declares the setting's choices from it
// (scene/settings.cpp), the renderer reads the typed value through it (choice_value), and
// to_string / parse (render/settings.h) print and parse with it. Table order is the order the
// choices are listed in messages, `--help` and docs/settings.md.
#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace nf::scene {

template <typename E>
struct ChoiceName {
  E value;
  const char* name;
};

// ---- luminaires (light-field sampling, docs/sampling.md)
// What draws the samples s_k (docs/sampling.md, "Methods").
enum class Method { ours, paper, uniform, uniform_equal, ours_equal, global };
// Where the 2D sample points come from. (Named SamplerKind: `Sampler` is the pipeline class.)
enum class SamplerKind { halton, halton_scrambled, random };
// How K_m(p) = K A_m / A is rounded (Eq. 12). `roulette` and `min1` are unbiased.
enum class Balance { paper, min1, roulette };
// CDF inversion: modified secant (paper §5) or the bisection baseline.
enum class SearchKind { secant, binary };
// Per-image passes as in the paper (Step 1 per image, Step 2 per image) or one fused pass.
enum class Structure { per_image, fused };
// Many instances (docs/sampling.md "Light selection"): every instance at every pixel (`all`), or one
// instance per pixel and frame drawn with probability q_i(p) from a flat per-pixel CDF (`flat`);
// `automatic` ("auto") is `flat` from kAutoSelectionInstances instances on, `all` below (measured
// crossover of the equal-time error, bench/results/selection/README.md).
enum class LightSelection { all, flat, automatic };
// The estimate f_i(p) the selection draws from (docs/sampling.md "Two kinds of light", "The bound"):
// the direction table's intensity estimate (`table`, the default: it measured better at N = 32 and
// 128, bench/results/selection/README.md run 4) or the bound of the instance's contribution E_i(p).
enum class SelectionEstimate { table, bound };
// MIS of the light-field samples with BRDF samples (docs/mis.md): off, balance or power heuristic.
enum class Mis { none, balance, power };
// What K_m(p) is balanced from (docs/sampling.md "Balancing from block estimates"): the block estimate
// of A_m(p) (exact A_m(p) only for the images that get samples) or the exact A_m(p) of every image.
// blocks applies to ours, paper and uniform (fused pass); the others always balance from exact.
enum class BalanceEstimate { blocks, exact };
// ---- frame
enum class Visibility { none, shadowmaps };
enum class VisibilityPass { opencl, gl };  // where Step 0's per-pixel shadow-map test runs
// ---- environment (docs/environment.md)
enum class EnvGlossy { mc, fis, fis_rotated, env_is, env_fis, regular };
enum class EnvKernel { point, integral };
enum class EnvFilter { box, gauss4, gauss6 };
enum class EnvParam { latlong, paraboloid };
enum class EnvDiffuse { sh, mc };
enum class EnvBackground { show, hide };
enum class EnvVisibilityKind { none, sh };
// ---- indirect (docs/indirect.md)
enum class Indirect { none, vsgl };
enum class VsglKernel { point, integral };
enum class VsglPoints { hammersley, fibonacci };
enum class VsglSplit { none, axis };

// The tables, found by overload on the enum type: choice_table(E{}).
#define NF_CHOICE_TABLE(E, ...)                                 \
  inline constexpr ChoiceName<E> k##E##Names[] = {__VA_ARGS__}; \
  constexpr std::span<const ChoiceName<E>> choice_table(E) { return k##E##Names; }

NF_CHOICE_TABLE(Method, {Method::ours, "ours"}, {Method::paper, "paper"}, {Method::uniform, "uniform"},
                {Method::uniform_equal, "uniform-equal"}, {Method::ours_equal, "ours-equal"},
                {Method::global, "global"})
NF_CHOICE_TABLE(SamplerKind, {SamplerKind::halton, "halton"}, {SamplerKind::halton_scrambled, "halton-scrambled"},
                {SamplerKind::random, "random"})
NF_CHOICE_TABLE(Balance, {Balance::paper, "paper"}, {Balance::min1, "min1"}, {Balance::roulette, "roulette"})
NF_CHOICE_TABLE(SearchKind, {SearchKind::secant, "secant"}, {SearchKind::binary, "binary"})
NF_CHOICE_TABLE(Structure, {Structure::per_image, "per-image"}, {Structure::fused, "fused"})
NF_CHOICE_TABLE(LightSelection, {LightSelection::automatic, "auto"}, {LightSelection::all, "all"},
                {LightSelection::flat, "flat"})
NF_CHOICE_TABLE(SelectionEstimate, {SelectionEstimate::table, "table"}, {SelectionEstimate::bound, "bound"})
NF_CHOICE_TABLE(Mis, {Mis::none, "none"}, {Mis::balance, "balance"}, {Mis::power, "power"})
NF_CHOICE_TABLE(BalanceEstimate, {BalanceEstimate::blocks, "blocks"}, {BalanceEstimate::exact, "exact"})
NF_CHOICE_TABLE(Visibility, {Visibility::none, "none"}, {Visibility::shadowmaps, "shadowmaps"})
NF_CHOICE_TABLE(VisibilityPass, {VisibilityPass::opencl, "opencl"}, {VisibilityPass::gl, "gl"})
NF_CHOICE_TABLE(EnvGlossy, {EnvGlossy::mc, "mc"}, {EnvGlossy::fis, "fis"}, {EnvGlossy::fis_rotated, "fis-rotated"},
                {EnvGlossy::env_is, "env-is"}, {EnvGlossy::env_fis, "env-fis"}, {EnvGlossy::regular, "regular"})
NF_CHOICE_TABLE(EnvKernel, {EnvKernel::point, "point"}, {EnvKernel::integral, "integral"})
NF_CHOICE_TABLE(EnvFilter, {EnvFilter::box, "box"}, {EnvFilter::gauss4, "gauss4"}, {EnvFilter::gauss6, "gauss6"})
NF_CHOICE_TABLE(EnvParam, {EnvParam::latlong, "latlong"}, {EnvParam::paraboloid, "paraboloid"})
NF_CHOICE_TABLE(EnvDiffuse, {EnvDiffuse::sh, "sh"}, {EnvDiffuse::mc, "mc"})
NF_CHOICE_TABLE(EnvBackground, {EnvBackground::show, "show"}, {EnvBackground::hide, "hide"})
NF_CHOICE_TABLE(EnvVisibilityKind, {EnvVisibilityKind::none, "none"}, {EnvVisibilityKind::sh, "sh"})
NF_CHOICE_TABLE(Indirect, {Indirect::none, "none"}, {Indirect::vsgl, "vsgl"})
NF_CHOICE_TABLE(VsglKernel, {VsglKernel::point, "point"}, {VsglKernel::integral, "integral"})
NF_CHOICE_TABLE(VsglPoints, {VsglPoints::hammersley, "hammersley"}, {VsglPoints::fibonacci, "fibonacci"})
NF_CHOICE_TABLE(VsglSplit, {VsglSplit::none, "none"}, {VsglSplit::axis, "axis"})
#undef NF_CHOICE_TABLE

// The names of E's choices in table order.
template <typename E>
std::vector<std::string> choice_names() {
  std::vector<std::string> out;
  for (const auto& c : choice_table(E{})) out.emplace_back(c.name);
  return out;
}

// The name of a value ("?" for a value outside the table).
template <typename E>
std::string choice_name(E v) {
  for (const auto& c : choice_table(E{}))
    if (c.value == v) return c.name;
  return "?";
}

// Throws nf::Error "<what>: unknown value '<text>' (valid: a, b, c)".
[[noreturn]] void fail_unknown_choice(const std::string& what, const std::string& text,
                                      const std::vector<std::string>& names);

// The value called `text` ('_' is accepted for '-'); unknown names throw (fail_unknown_choice).
// On a declared setting (scene::RenderSettings, validated by the registry) it cannot throw.
template <typename E>
E choice_value(std::string text, const std::string& what = "choice") {
  for (char& ch : text)
    if (ch == '_') ch = '-';
  for (const auto& c : choice_table(E{}))
    if (text == c.name) return c.value;
  fail_unknown_choice(what, text, choice_names<E>());
}

}  // namespace nf::scene
