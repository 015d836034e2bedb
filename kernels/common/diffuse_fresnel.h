#ifndef NEARFIELD_COMMON_DIFFUSE_FRESNEL_H
#define NEARFIELD_COMMON_DIFFUSE_FRESNEL_H
/* The pre-integrated diffuse Fresnel factor of the glTF metallic-roughness BRDF
   (docs/environment.md, "Diffuse Fresnel"). Its diffuse lobe is (1 - F(v.h)) (1 - metallic) base / pi
   with Schlick's F = F0 + (1 - F0) (1 - v.h)^5 inside the integral over l. Under a radiance that
   is constant over the hemisphere, the lobe reflects (1 - metallic) base L times the cosine-
   weighted mean of 1 - F:
     a(n.v) = (1 / pi) int_H (1 - F(v.h(l))) (n.l) dl = (1 - F0) (1 - s(n.v)),
     s(mu) = (1 / pi) int_H (1 - v.h)^5 (n.l) dl,
   a function of mu = n.v alone (isotropic in l about n). s is tabulated at mu = k / 32 (k = 0..32)
   from a 1500 x 1500 midpoint rule in the cosine-warped square (converged to < 1e-7) and read
   linearly; it falls from 0.028 at grazing to 8e-5 at normal view, where F(n.v) (the former
   approximation) goes from 1 to 0: at grazing views F(n.v) removed the whole diffuse term. */
#include "common/lanes.h"

NF_INLINE float nf_diffuse_fresnel_s(float mu) {
  const float s[33] = {0.0281555f, 0.0257533f, 0.0235052f, 0.0214069f, 0.0194530f, 0.0176373f, 0.0159534f,
                       0.0143947f, 0.0129546f, 0.0116265f, 0.0104042f, 0.0092812f, 0.0082518f, 0.0073100f,
                       0.0064504f, 0.0056676f, 0.0049567f, 0.0043128f, 0.0037313f, 0.0032079f, 0.0027385f,
                       0.0023191f, 0.0019461f, 0.0016159f, 0.0013253f, 0.0010710f, 0.0008503f, 0.0006601f,
                       0.0004980f, 0.0003614f, 0.0002479f, 0.0001555f, 0.0000819f};
  const float x = clamp(mu, 0.0f, 1.0f) * 32.0f;
  const int i = min((int)x, 31);
  return mix(s[i], s[i + 1], x - (float)i);
}

/* (1 - F0) (1 - s(n.v)): the cosine-weighted mean of 1 - F(v.h) over the hemisphere, per channel. */
NF_INLINE float3 nf_diffuse_fresnel(float3 f0, float nv) { return (1.0f - f0) * (1.0f - nf_diffuse_fresnel_s(nv)); }

#endif
