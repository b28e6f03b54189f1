// The path tracer (ref/trace/pathtrace.h, SPEC §8) is unbiased on cases with a closed form: the
// mean of many 1-spp frames against it, within 5 standard errors estimated from the samples'
// own variance.
//   furnace: inside a closed box whose every wall emits Le and reflects albedo a, a path that
//     sees a wall, estimates its direct light by NEE and bounces B times carries
//     Le (1 + a + ... + a^(B+1)) (the emission at secondary vertices is counted through NEE only)
//   quad light over a plane: the plane's radiance is a Le F(P) with F the point-to-rectangle
//     form factor (Lambert's polygon formula); the light has no geometry, so secondary rays leave
#include <doctest/doctest.h>

#include <cmath>

#include "ref/modes/modes.h"
#include "ref/trace/bsdf.h"
#include "ref/trace/pathtrace.h"

using namespace fovref;

namespace {

// Two triangles p0 p1 p2, p0 p2 p3 with the normal of cross(p1 - p0, p2 - p0).
void add_quad(Scene& scene, glm::vec3 p0, glm::vec3 p1, glm::vec3 p2, glm::vec3 p3, int material) {
    const glm::vec3 n = glm::normalize(glm::cross(p1 - p0, p2 - p0));
    for (const glm::vec3& p : {p0, p1, p2, p0, p2, p3}) {
        scene.positions.push_back(p);
        scene.normals.push_back(n);
        scene.uvs.push_back({0, 0});
    }
    scene.material_ids.push_back(material);
    scene.material_ids.push_back(material);
}

struct Mean {
    double sum = 0.0, sum2 = 0.0;
    long n = 0;
    void add(double v) {
        sum += v;
        sum2 += v * v;
        ++n;
    }
    double mean() const { return sum / static_cast<double>(n); }
    double standard_error() const {
        const double m = mean();
        return std::sqrt(std::max(0.0, sum2 / static_cast<double>(n) - m * m) /
                         static_cast<double>(n));
    }
};

std::vector<FrameResult> render_frames(const Scene& scene, int frames, int bounces) {
    RenderSettings s;
    s.width = 32;
    s.height = 18;
    s.frame_count = frames;
    s.time_step = 0.0f;
    if (bounces > 1) s.params.set("max_bounces", std::to_string(bounces));
    s.requested = {"all"};
    return render(&scene, "pathtrace", s);
}

}  // namespace

TEST_CASE("pathtrace: a furnace box returns Le (1 + a + ... + a^(B+1)) on average") {
    Scene scene;
    scene.source = "test";
    const float a = 0.5f;
    scene.materials.push_back(Material{"wall", glm::vec3(a), -1, glm::vec3(1.0f)});
    // The cube [-1, 1]^3 with every face's normal pointing inwards.
    const glm::vec3 c[8] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                            {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
    add_quad(scene, c[0], c[1], c[2], c[3], 0);  // z = -1, normal +z
    add_quad(scene, c[4], c[7], c[6], c[5], 0);  // z = +1, normal -z
    add_quad(scene, c[0], c[4], c[5], c[1], 0);  // y = -1, normal +y
    add_quad(scene, c[3], c[2], c[6], c[7], 0);  // y = +1, normal -y
    add_quad(scene, c[0], c[3], c[7], c[4], 0);  // x = -1, normal +x
    add_quad(scene, c[1], c[5], c[6], c[2], 0);  // x = +1, normal -x
    scene.camera = look_at({0.1f, 0.2f, 0.3f}, {0.5f, -0.2f, -1.0f}, {0, 1, 0}, 60.0f);
    finalize_scene(scene);
    REQUIRE(scene.lights.size() == 12);
    for (const int bounces : {1, 3}) {
        CAPTURE(bounces);
        double expected = 0.0, power = 1.0;
        for (int k = 0; k <= bounces + 1; ++k, power *= a) expected += power;
        Mean mean;
        for (const FrameResult& f : render_frames(scene, 96, bounces)) {
            const Image& l = f.find("final")->image;
            for (int p = 0; p < l.width * l.height; ++p) mean.add(l.data[3 * p]);
            CHECK(f.counters.get("paths") == 32 * 18);
            CHECK(f.counters.get("paths_ended_background") == 0);  // a closed box
        }
        MESSAGE("furnace B = ", bounces, ": mean ", mean.mean(), " +- ", mean.standard_error(),
                ", expected ", expected);
        CHECK(std::fabs(mean.mean() - expected) < 5.0 * mean.standard_error() + 1e-3);
        CHECK(mean.standard_error() < 0.02);  // the test has power
    }
}

TEST_CASE("pathtrace: a quad light over a plane gives a Le F, F the rectangle's form factor") {
    Scene scene;
    scene.source = "test";
    const float a = 0.7f, le = 2.0f;
    scene.materials.push_back(Material{"floor", glm::vec3(a)});
    add_quad(scene, {-50, 0, -50}, {-50, 0, 50}, {50, 0, 50}, {50, 0, -50}, 0);  // y = 0, normal +y
    Light light;
    light.type = Light::Type::quad;
    light.position = {-0.5f, 1.0f, -0.5f};
    light.edge_u = {1.0f, 0.0f, 0.0f};
    light.edge_v = {0.0f, 0.0f, 1.0f};  // cross(u, v) = (0, -1, 0): emits downwards
    light.intensity = glm::vec3(le);
    scene.lights.push_back(light);
    scene.camera = look_at({0.0f, 3.0f, 2.5f}, {0.0f, 0.0f, 0.0f}, {0, 1, 0}, 60.0f);
    finalize_scene(scene);
    // Lambert: F = 1/(2 pi) sum_i angle(v_i, v_i+1) (n . unit(v_i x v_i+1)), v_i = corner - P.
    const glm::dvec3 corners[4] = {{-0.5, 1, -0.5}, {0.5, 1, -0.5}, {0.5, 1, 0.5}, {-0.5, 1, 0.5}};
    const auto form_factor = [&](glm::dvec3 p) {
        double f = 0.0;
        for (int i = 0; i < 4; ++i) {
            const glm::dvec3 v0 = glm::normalize(corners[i] - p);
            const glm::dvec3 v1 = glm::normalize(corners[(i + 1) % 4] - p);
            const glm::dvec3 g = glm::normalize(glm::cross(v0, v1));
            f += std::acos(std::clamp(glm::dot(v0, v1), -1.0, 1.0)) * g.y;
        }
        return std::fabs(f) / (2.0 * 3.14159265358979323846);
    };
    Mean error;  // rendered - expected, per pixel and frame
    double expected_mean = 0.0;
    for (const FrameResult& f : render_frames(scene, 48, 1)) {
        const Image& l = f.find("final")->image;
        const Image& position = f.find("gbuffer_world_position")->image;
        const Image& id = f.find("gbuffer_primitive_id")->image;
        for (int y = 0; y < l.height; ++y)
            for (int x = 0; x < l.width; ++x) {
                REQUIRE(id.at(x, y) >= 0.0f);  // the plane fills the view
                const glm::dvec3 p{position.at(x, y, 0), position.at(x, y, 1),
                                   position.at(x, y, 2)};
                const double expected = a * le * form_factor(p);
                expected_mean += expected;
                error.add(l.at(x, y, 0) - expected);
            }
        CHECK(f.counters.get("paths_ended_background") == 32 * 18);  // secondary rays leave
    }
    expected_mean /= static_cast<double>(error.n);
    MESSAGE("quad light: mean error ", error.mean(), " +- ", error.standard_error(),
            " (mean radiance ", expected_mean, ")");
    CHECK(std::fabs(error.mean()) < 5.0 * error.standard_error() + 1e-4);
    CHECK(error.standard_error() < 0.02 * expected_mean);
}

TEST_CASE(
    "pathtrace: a glossy plane under a quad light: NEE with the GGX lobe matches the "
    "quadrature over the light") {
    Scene scene;
    scene.source = "test";
    const float le = 2.0f;
    Material floor{"glossy", glm::vec3(0.3f)};
    floor.specular = glm::vec3(0.5f);
    floor.roughness = 0.4f;
    scene.materials.push_back(floor);
    add_quad(scene, {-50, 0, -50}, {-50, 0, 50}, {50, 0, 50}, {50, 0, -50}, 0);
    Light light;
    light.type = Light::Type::quad;
    light.position = {-0.5f, 1.0f, -0.5f};
    light.edge_u = {1.0f, 0.0f, 0.0f};
    light.edge_v = {0.0f, 0.0f, 1.0f};
    light.intensity = glm::vec3(le);
    scene.lights.push_back(light);
    scene.camera = look_at({0.0f, 1.5f, 2.0f}, {0.0f, 0.0f, 0.0f}, {0, 1, 0}, 60.0f);
    finalize_scene(scene);
    // The expected radiance of floor point P seen from the camera: the integral over the light
    // of f(l, v) Le cos cos_l / d^2 dA (midpoint rule, 48 x 48), f from bsdf_eval (whose GGX
    // lobe tests/trace/ggx_test.cpp checks against quadrature); secondary rays leave the scene.
    const Bsdf b = make_bsdf(floor, floor.albedo, glm::vec3(0, 1, 0));
    const auto expected_at = [&](glm::vec3 p) {
        const glm::vec3 v = glm::normalize(scene.camera.position - p);
        double sum = 0.0;
        const int n = 48;
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) {
                const glm::vec3 y{-0.5f + (static_cast<float>(i) + 0.5f) / n, 1.0f,
                                  -0.5f + (static_cast<float>(j) + 0.5f) / n};
                const glm::vec3 d = y - p;
                const float d2 = glm::dot(d, d);
                const glm::vec3 l = d / std::sqrt(d2);
                sum += static_cast<double>(bsdf_eval(b, l, v).x) * le * l.y * l.y / d2 / (n * n);
            }
        return sum;
    };
    Mean error;
    double expected_mean = 0.0;
    for (const FrameResult& f : render_frames(scene, 64, 1)) {
        const Image& l = f.find("final")->image;
        const Image& position = f.find("gbuffer_world_position")->image;
        for (int y = 0; y < l.height; ++y)
            for (int x = 0; x < l.width; ++x) {
                const glm::vec3 p{position.at(x, y, 0), position.at(x, y, 1), position.at(x, y, 2)};
                const double expected = expected_at(p);
                expected_mean += expected;
                error.add(l.at(x, y, 0) - expected);
            }
    }
    expected_mean /= static_cast<double>(error.n);
    MESSAGE("glossy quad light: mean error ", error.mean(), " +- ", error.standard_error(),
            " (mean radiance ", expected_mean, ")");
    CHECK(std::fabs(error.mean()) < 5.0 * error.standard_error() + 2e-4);
    CHECK(error.standard_error() < 0.02 * expected_mean);
}

TEST_CASE("pathtrace: cosine_direction is a unit vector in the hemisphere of n") {
    for (const glm::vec3& n : {glm::vec3(0, 0, 1), glm::vec3(0, 0, -1), glm::vec3(0, 1, 0),
                               glm::normalize(glm::vec3(1, -2, 0.5f))})
        for (const float u1 : {0.0f, 0.3f, 0.999f})
            for (const float u2 : {0.0f, 0.25f, 0.7f}) {
                const glm::vec3 d = cosine_direction(n, u1, u2);
                CHECK(glm::length(d) == doctest::Approx(1.0f).epsilon(1e-5));
                CHECK(glm::dot(d, n) >= 0.0f);
                // The cosine to n is sqrt(1 - u1) (the pdf's cos / pi).
                CHECK(glm::dot(d, n) == doctest::Approx(std::sqrt(1.0f - u1)).epsilon(1e-4));
            }
}
