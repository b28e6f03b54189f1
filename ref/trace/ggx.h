// The GGX (Trowbridge-Reitz) microfacet lobe for glossy materials (SPEC §8: "glossy: GGX
// visible-normal sampling with the material's roughness"), as pure functions in a local frame
// whose z axis is the shading normal. Not yet used by the path tracer (docs/pathtrace.md).
// clang-format off
//
//   alpha = roughness^2 (Material::roughness), clamped to [1e-3, 1]
//   D(h)      = alpha^2 / (pi ((h.z)^2 (alpha^2 - 1) + 1)^2)
//   Lambda-based Smith masking, height-correlated (Heitz 2014):
//     G1(v)   = 2 v.z / (v.z + sqrt(alpha^2 + (1 - alpha^2) v.z^2))
//     G2(l,v) = 2 l.z v.z / (v.z sqrt(alpha^2 + (1 - alpha^2) l.z^2) + l.z sqrt(alpha^2 + (1 - alpha^2) v.z^2))
//   Fresnel (Schlick): F = F0 + (1 - F0) (1 - v.h)^5, F0 = Material::specular
//   f(l, v)   = D(h) G2(l, v) F / (4 l.z v.z),  h = normalize(l + v)
//   sampling: Heitz 2018's visible normals, pdf(h) = G1(v) max(0, v.h) D(h) / v.z,
//             pdf(l) = pdf(h) / (4 v.h)
// clang-format on
#pragma once

#include <glm/glm.hpp>

namespace fovref {

/// alpha = roughness^2, clamped to [1e-3, 1] (a perfect mirror is out of this lobe's range).
float ggx_alpha(float roughness);

float ggx_d(glm::vec3 h, float alpha);
float ggx_g1(glm::vec3 v, float alpha);
float ggx_g2(glm::vec3 l, glm::vec3 v, float alpha);
glm::vec3 ggx_fresnel(glm::vec3 f0, float v_dot_h);

/// f(l, v) (without the cosine); 0 when l or v is below the surface.
glm::vec3 ggx_brdf(glm::vec3 l, glm::vec3 v, float alpha, glm::vec3 f0);

/// A microfacet normal visible from v (v.z > 0) from two numbers in [0, 1) (Heitz 2018).
glm::vec3 ggx_sample_visible_normal(glm::vec3 v, float alpha, float u1, float u2);

/// The density of l = reflect(-v, h) when h is sampled by ggx_sample_visible_normal.
float ggx_pdf(glm::vec3 l, glm::vec3 v, float alpha);

}  // namespace fovref
