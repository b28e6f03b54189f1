#include "ref/trace/bsdf.h"

#include <algorithm>
#include <cmath>

#include "ref/trace/ggx.h"
#include "ref/trace/pathtrace.h"

namespace fovref {

namespace {

constexpr float inv_pi = 0.318309886183790671538f;

float max_component(glm::vec3 v) { return std::max(v.x, std::max(v.y, v.z)); }

glm::vec3 to_local(const Bsdf& b, glm::vec3 w) {
    return {glm::dot(w, b.t), glm::dot(w, b.s), glm::dot(w, b.n)};
}

}  // namespace

void duff_basis(glm::vec3 n, glm::vec3& t, glm::vec3& s) {
    const float sign = n.z >= 0.0f ? 1.0f : -1.0f;
    const float a = -1.0f / (sign + n.z);
    const float b = n.x * n.y * a;
    t = {1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x};
    s = {b, sign + n.y * n.y * a, -n.y};
}

Bsdf make_bsdf(const Material& material, glm::vec3 albedo, glm::vec3 n_s) {
    Bsdf b;
    b.albedo = albedo;
    b.n = n_s;
    duff_basis(n_s, b.t, b.s);
    const float spec = max_component(material.specular);
    if (spec > 0.0f) {
        b.specular = material.specular;
        b.alpha = ggx_alpha(material.roughness);
        const float diffuse = std::max(max_component(albedo), 0.0f);
        b.p_specular = spec / (spec + diffuse);
    }
    return b;
}

glm::vec3 bsdf_eval(const Bsdf& b, glm::vec3 l, glm::vec3 v) {
    glm::vec3 f = b.albedo * inv_pi;
    if (b.glossy()) f += ggx_brdf(to_local(b, l), to_local(b, v), b.alpha, b.specular);
    return f;
}

float bsdf_pdf(const Bsdf& b, glm::vec3 l, glm::vec3 v) {
    const float cos_l = std::max(0.0f, glm::dot(l, b.n));
    const float diffuse = cos_l * inv_pi;
    if (!b.glossy()) return diffuse;
    return b.p_specular * ggx_pdf(to_local(b, l), to_local(b, v), b.alpha) +
           (1.0f - b.p_specular) * diffuse;
}

bool bsdf_sample(const Bsdf& b, glm::vec3 v, float u_lobe, float u1, float u2, glm::vec3& l,
                 glm::vec3& weight) {
    if (!b.glossy()) {
        l = cosine_direction(b.n, u1, u2);
        weight = b.albedo;  // (albedo / pi) cos / (cos / pi)
        return true;
    }
    if (u_lobe < b.p_specular) {
        const glm::vec3 v_local = to_local(b, v);
        if (!(v_local.z > 0.0f)) return false;
        const glm::vec3 h = ggx_sample_visible_normal(v_local, b.alpha, u1, u2);
        const glm::vec3 l_local = h * (2.0f * glm::dot(v_local, h)) - v_local;
        if (!(l_local.z > 0.0f)) return false;
        l = b.t * l_local.x + b.s * l_local.y + b.n * l_local.z;
    } else {
        l = cosine_direction(b.n, u1, u2);
    }
    const float pdf = bsdf_pdf(b, l, v);
    const float cos_l = glm::dot(l, b.n);
    if (!(pdf > 0.0f) || !(cos_l > 0.0f)) return false;
    weight = bsdf_eval(b, l, v) * (cos_l / pdf);
    return true;
}

}  // namespace fovref
