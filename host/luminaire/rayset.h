#pragma once
// A measured or simulated ray set (docs/measured-data.md): each ray is a start position, a unit
// direction and the flux it carries. Readers convert positions to metres; the flux stays in the
// unit the file states (lm for luminous flux, W for radiant flux).
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace nf::lum {

enum class FluxKind { luminous, radiant };  // lm | W
const char* flux_unit(FluxKind k);          // "lm" | "W"

struct RaySet {
  std::vector<glm::dvec3> position;   // metres
  std::vector<glm::dvec3> direction;  // unit vectors
  std::vector<double> flux;           // per ray, in flux_unit(kind)
  FluxKind kind = FluxKind::radiant;
  std::string source;              // the file it came from
  std::string format;              // "TM-25" | "LightTools ASCII" | "generated"
  double header_flux = -1.0;       // total flux the header states (< 0: none)
  std::vector<std::string> notes;  // what the reader skipped or noticed (spectra, Stokes, ...)
  // Colour from the file's spectral data (docs/measured-data.md, "Colour"): linear sRGB clipped
  // to the gamut with Rec. 709 luminance 1 (color::unit_luminance_rgb). Empty: no spectral data
  // (white); one entry: every ray has that colour; else one per ray.
  std::vector<glm::dvec3> colour;
  glm::dvec3 xyz{0.0};        // sum over rays of flux * XYZ / Y (unclipped; 0 without colour)
  std::string colour_source;  // where the colour came from, e.g. "spectral table 1 (86 samples, 450..620 nm)"

  std::size_t size() const { return flux.size(); }
  double total_flux() const;  // sum of the rays' flux (double precision)
  void add(glm::dvec3 p, glm::dvec3 d, double f);
};

// Reads a TM-25 binary ray file or a LightTools ASCII ray file, chosen by content (TM-25 files
// start with the magic "TM25"; LightTools files are text with `lt_` keys).
RaySet read_rayset(const std::filesystem::path& file);

}  // namespace nf::lum
