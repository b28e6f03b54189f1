// The path tracer's BSDF (SPEC §8; docs/pathtrace.md, "Materials"): Lambert plus, for a material
// whose `specular` is not zero, the GGX lobe of ggx.h:
//
//   f(l, v) = albedo / pi + f_GGX(l, v; alpha = ggx_alpha(roughness), F0 = specular)
//
// (the two lobes are added without energy coupling, as the scene format defines materials).
// Directions are unit vectors pointing away from the surface; the GGX lobe is evaluated in the
// local frame of the shading normal n (Duff et al. 2017's basis t, s, n, as cosine_direction).
//
// Sampling (one secondary direction, SPEC §8): the GGX lobe with probability
// p = max(specular) / (max(specular) + max(albedo)), by Heitz 2018's visible normals
// (l = reflect(-v, h)), else cosine-weighted; the weight f cos / pdf uses the mixture density
// p pdf_GGX(l) + (1 - p) cos / pi (one-sample mixture: unbiased for either lobe). A diffuse
// material (specular 0) takes the cosine direction with weight albedo, as before GGX.
#pragma once

#include <glm/glm.hpp>

#include "ref/scene/scene.h"

namespace fovref {

struct Bsdf {
    glm::vec3 albedo{0.0f};
    glm::vec3 specular{0.0f};  ///< F0 of the GGX lobe (0: diffuse only)
    float alpha = 1.0f;
    float p_specular = 0.0f;                       ///< probability of sampling the GGX lobe
    glm::vec3 t{1, 0, 0}, s{0, 1, 0}, n{0, 0, 1};  ///< the local frame (n the shading normal)
    bool glossy() const { return p_specular > 0.0f; }
};

/// The BSDF of `material` at a surface point of albedo `albedo` (texture applied) and shading
/// normal n_s (turned to the incoming side).
Bsdf make_bsdf(const Material& material, glm::vec3 albedo, glm::vec3 n_s);

/// The orthonormal basis (t, s) of Duff et al. 2017 around unit n.
void duff_basis(glm::vec3 n, glm::vec3& t, glm::vec3& s);

/// f(l, v) (without the cosine), world directions; the GGX part is 0 below the surface.
glm::vec3 bsdf_eval(const Bsdf& bsdf, glm::vec3 l, glm::vec3 v);

/// The mixture density of bsdf_sample's direction l (solid angle).
float bsdf_pdf(const Bsdf& bsdf, glm::vec3 l, glm::vec3 v);

/// One direction l from three numbers in [0, 1) (u_lobe chooses the lobe; a diffuse BSDF does not
/// use it) and its weight f cos / pdf. False when the GGX reflection points below the shading
/// surface (the path is absorbed).
bool bsdf_sample(const Bsdf& bsdf, glm::vec3 v, float u_lobe, float u1, float u2, glm::vec3& l,
                 glm::vec3& weight);

}  // namespace fovref
