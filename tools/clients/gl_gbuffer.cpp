// gl_gbuffer: a real OpenGL client of the oracle. It renders the G-buffer of a fovref golden
// bundle with OpenGL 4.5 through EGL on Mesa's surfaceless platform (no display, no window: on a
// machine without a GPU that is Mesa's llvmpipe, a conformant OpenGL 4.5 implementation; OSMesa,
// which this client used before, is gone from Mesa 25.1), writes each channel under the bundle's
// buffer name, and `fovref diff` checks it:
//
//   fovref golden export cornell-basic-raster gold --param fill_rule=gl --with-scene
//   gl_gbuffer gold out
//   fovref diff gold out --profile gpu-raster --require gbuffer_primitive_id,...
//
// It is deliberately small, and it depends on nothing of fovref's: it reads what a GPU engine
// would read — the bundle's manifest.json (resolution, per-frame camera) and the exported scene
// (scene/scene.obj + scene.mtl + textures) — and writes plain PFM files. A Vulkan, D3D or CUDA
// client has the same shape: load the OBJ in file order, draw with fovref's camera, dump the
// attachments. The conventions it follows are fovref's (docs/diff.md, "Writing a client"):
//
//   primitive id    index of the triangle in the OBJ (gl_PrimitiveID of one draw in file order)
//   material id     index of its material in the MTL (usemtl order = fovref's material index)
//   camera          position, right, up, forward and tan(vfov/2) from the manifest (not
//                   recomputed: a GPU's tan differs in the last bits)
//   projection      clip = (dot(d,R) / (tan_half * W/H), dot(d,U) / tan_half, near, dot(d,F)),
//                   d = p - camera: fovref's pinhole with OpenGL's y-up window; reversed-Z
//                   (depth = near / z, GL_GREATER, 32-bit float depth) and no far plane
//   fill rule       OpenGL's: compare with a bundle rendered with --param fill_rule=gl
//   background      ids -1, every other channel 0
//   rows            glReadPixels returns the bottom row first, which is PFM's row order
//
// Buffers written: gbuffer_view_depth, gbuffer_hit_distance, gbuffer_world_position,
// gbuffer_shading_normal, gbuffer_geometric_normal, gbuffer_albedo, gbuffer_material_id,
// gbuffer_primitive_id (frame f as f%03d_<name>.pfm). Exit 0 on success, 2 on any error.
#define GL_GLEXT_PROTOTYPES 1
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/gl.h>
// (GL/gl.h first: GL/glext.h extends it)
#include <GL/glext.h>
#include <tiny_obj_loader.h>

#include "tools/clients/common/files.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using json = nlohmann::json;

struct Failure : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// ---- Files -------------------------------------------------------------------------------------

// PFM: "PF" (RGB) or "Pf" (grey), size, negative scale = little-endian, rows bottom to top.
struct Texture {
    int width = 0, height = 0;
    std::vector<float> rgb;  // bottom row first, as in the file and as OpenGL wants it
};

Texture read_pfm_rgb(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::string magic;
    Texture t;
    double scale = 0;
    if (!(in >> magic >> t.width >> t.height >> scale) || magic != "PF" || scale >= 0 ||
        t.width <= 0 || t.height <= 0)
        throw Failure(path + ": not a little-endian RGB PFM texture");
    in.get();  // the single whitespace after the header
    t.rgb.resize(static_cast<std::size_t>(t.width) * t.height * 3);
    if (!in.read(reinterpret_cast<char*>(t.rgb.data()),
                 static_cast<std::streamsize>(t.rgb.size() * sizeof(float))))
        throw Failure(path + ": truncated");
    return t;
}

// ---- Scene -------------------------------------------------------------------------------------

struct Material {
    float albedo[3] = {0, 0, 0};
    int texture = -1;
};

struct Scene {
    // One vertex per triangle corner, in file order: primitive k = vertices 3k .. 3k + 2.
    std::vector<float> position, normal, uv;
    std::vector<int> material;  // per vertex (the triangle's)
    std::vector<Material> materials;
    std::vector<Texture> textures;
    float radius = 1.0f;  // bounding-box half diagonal: for the near plane
};

Scene load_scene(const std::string& obj_path) {
    tinyobj::ObjReaderConfig config;
    config.triangulate = false;  // fovref exports triangles only
    config.mtl_search_path = obj_path.substr(0, obj_path.find_last_of('/') + 1);
    tinyobj::ObjReader reader;
    if (!reader.ParseFromFile(obj_path, config)) throw Failure(obj_path + ": " + reader.Error());
    const tinyobj::attrib_t& attrib = reader.GetAttrib();
    Scene scene;
    for (const tinyobj::material_t& m : reader.GetMaterials()) {
        Material material;
        for (int c = 0; c < 3; ++c) material.albedo[c] = m.diffuse[c];
        if (!m.diffuse_texname.empty()) {
            material.texture = static_cast<int>(scene.textures.size());
            scene.textures.push_back(read_pfm_rgb(config.mtl_search_path + m.diffuse_texname));
        }
        scene.materials.push_back(material);
    }
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (const tinyobj::shape_t& shape : reader.GetShapes()) {
        for (std::size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f) {
            if (shape.mesh.num_face_vertices[f] != 3)
                throw Failure(obj_path + ": face " + std::to_string(f) + " is not a triangle");
            for (std::size_t k = 0; k < 3; ++k) {
                const tinyobj::index_t& i = shape.mesh.indices[3 * f + k];
                for (int c = 0; c < 3; ++c) {
                    const float p = attrib.vertices[3 * i.vertex_index + c];
                    scene.position.push_back(p);
                    lo[c] = std::min(lo[c], p);
                    hi[c] = std::max(hi[c], p);
                    scene.normal.push_back(
                        i.normal_index >= 0 ? attrib.normals[3 * i.normal_index + c] : 0.0f);
                }
                for (int c = 0; c < 2; ++c)
                    scene.uv.push_back(
                        i.texcoord_index >= 0 ? attrib.texcoords[2 * i.texcoord_index + c] : 0.0f);
                scene.material.push_back(shape.mesh.material_ids[f]);
            }
        }
    }
    const float dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
    scene.radius = 0.5f * std::sqrt(dx * dx + dy * dy + dz * dz);
    return scene;
}

// ---- OpenGL ------------------------------------------------------------------------------------

GLuint compile(GLenum type, const char* source) {
    const GLuint shader = glCreateShader(type);
    glShaderSource(shader, 1, &source, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[4096];
        glGetShaderInfoLog(shader, sizeof log, nullptr, log);
        throw Failure(std::string("shader: ") + log);
    }
    return shader;
}

// The vertex shader projects with fovref's pinhole (SPEC §1) in OpenGL's y-up clip space.
const char* vertex_shader = R"(#version 450 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec2 uv;
layout(location = 3) in int material;
uniform vec3 camera, right, up, forward;
uniform float tan_half, aspect, near;
out vec3 v_position; out vec3 v_normal; out vec2 v_uv; flat out int v_material;
void main() {
    vec3 d = position - camera;
    vec3 view = vec3(dot(d, right), dot(d, up), dot(d, forward));
    gl_Position = vec4(view.x / (tan_half * aspect), view.y / tan_half, near, view.z);
    v_position = position; v_normal = normal; v_uv = uv; v_material = material;
})";

// The geometry shader adds the face normal (normalised cross product of the world edges, as
// fovref's geometric normal) and the primitive id: gl_PrimitiveIDIn counts from 0 in each draw,
// so the draw's first triangle index is added.
const char* geometry_shader = R"(#version 450 core
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;
uniform int first_primitive;
in vec3 v_position[]; in vec3 v_normal[]; in vec2 v_uv[]; flat in int v_material[];
out vec3 g_position; out vec3 g_normal; out vec2 g_uv;
flat out int g_material; flat out vec3 g_face_normal;
void main() {
    vec3 n = cross(v_position[1] - v_position[0], v_position[2] - v_position[0]);
    vec3 face = length(n) > 0.0 ? normalize(n) : vec3(0.0);
    for (int k = 0; k < 3; ++k) {
        gl_Position = gl_in[k].gl_Position;
        gl_PrimitiveID = gl_PrimitiveIDIn + first_primitive;
        g_position = v_position[k]; g_normal = v_normal[k]; g_uv = v_uv[k];
        g_material = v_material[0]; g_face_normal = face;
        EmitVertex();
    }
    EndPrimitive();
})";

// One output per G-buffer channel. Texture lookups: bilinear, repeat, v = 0 at the bottom row.
const char* fragment_shader = R"(#version 450 core
in vec3 g_position; in vec3 g_normal; in vec2 g_uv;
flat in int g_material; flat in vec3 g_face_normal;
uniform vec3 camera, forward;
uniform vec3 albedo; uniform bool textured; uniform sampler2D albedo_texture;
layout(location = 0) out float view_depth;
layout(location = 1) out float hit_distance;
layout(location = 2) out vec4 world_position;
layout(location = 3) out vec4 shading_normal;
layout(location = 4) out vec4 geometric_normal;
layout(location = 5) out vec4 albedo_out;
layout(location = 6) out int material_id;
layout(location = 7) out int primitive_id;
void main() {
    vec3 d = g_position - camera;
    view_depth = dot(d, forward);
    hit_distance = length(d);
    world_position = vec4(g_position, 0.0);
    float n = length(g_normal);
    shading_normal = vec4(n > 0.0 ? g_normal / n : g_face_normal, 0.0);
    geometric_normal = vec4(g_face_normal, 0.0);
    vec3 a = albedo;
    if (textured) a *= texture(albedo_texture, g_uv).rgb;
    albedo_out = vec4(a, 0.0);
    material_id = g_material;
    primitive_id = gl_PrimitiveID;
})";

struct Attachment {
    const char* name;
    GLenum internal_format, format, type;
    int channels;  // written to the PFM
};

const Attachment attachments[] = {
    {"gbuffer_view_depth", GL_R32F, GL_RED, GL_FLOAT, 1},
    {"gbuffer_hit_distance", GL_R32F, GL_RED, GL_FLOAT, 1},
    {"gbuffer_world_position", GL_RGBA32F, GL_RGBA, GL_FLOAT, 3},
    {"gbuffer_shading_normal", GL_RGBA32F, GL_RGBA, GL_FLOAT, 3},
    {"gbuffer_geometric_normal", GL_RGBA32F, GL_RGBA, GL_FLOAT, 3},
    {"gbuffer_albedo", GL_RGBA32F, GL_RGBA, GL_FLOAT, 3},
    {"gbuffer_material_id", GL_R32I, GL_RED_INTEGER, GL_INT, 1},
    {"gbuffer_primitive_id", GL_R32I, GL_RED_INTEGER, GL_INT, 1},
};
constexpr int attachment_count = sizeof attachments / sizeof attachments[0];

void check_gl(const char* where) {
    const GLenum e = glGetError();
    if (e != GL_NO_ERROR)
        throw Failure(std::string("OpenGL error ") + std::to_string(e) + " in " + where);
}

// Framebuffer: one texture per channel, a 32-bit float depth buffer.
void make_framebuffer(int width, int height) {
    GLuint fbo = 0, textures[attachment_count], depth = 0;
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glGenTextures(attachment_count, textures);
    GLenum draw_buffers[attachment_count];
    for (int k = 0; k < attachment_count; ++k) {
        glBindTexture(GL_TEXTURE_2D, textures[k]);
        glTexStorage2D(GL_TEXTURE_2D, 1, attachments[k].internal_format, width, height);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + k, GL_TEXTURE_2D, textures[k],
                               0);
        draw_buffers[k] = GL_COLOR_ATTACHMENT0 + k;
    }
    glGenRenderbuffers(1, &depth);
    glBindRenderbuffer(GL_RENDERBUFFER, depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, width, height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
    glDrawBuffers(attachment_count, draw_buffers);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw Failure("framebuffer incomplete");
}

// Background: ids -1, everything else 0; reversed-Z depth clears to 0. Then the depth test,
// two-sided triangles and the viewport.
void clear_and_set_state(int width, int height) {
    const GLfloat zero[4] = {0, 0, 0, 0};
    const GLint minus_one[4] = {-1, -1, -1, -1};
    for (int k = 0; k < attachment_count; ++k) {
        if (attachments[k].type == GL_INT)
            glClearBufferiv(GL_COLOR, k, minus_one);
        else
            glClearBufferfv(GL_COLOR, k, zero);
    }
    // OpenGL 4.5's glClipControl, looked up (libOpenGL need not export every 4.5 entry point)
    const auto clip_control =
        reinterpret_cast<PFNGLCLIPCONTROLPROC>(eglGetProcAddress("glClipControl"));
    if (!clip_control) throw Failure("EGL: no glClipControl");
    clip_control(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glClearDepth(0.0);
    glClear(GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);  // reversed-Z; the first drawn (lower id) wins ties
    glDisable(GL_CULL_FACE);  // two-sided, as fovref
    glViewport(0, 0, width, height);
}

// The shader program, in use, with the camera's uniforms.
GLuint make_program(const Scene& scene, const json& camera, int width, int height) {
    const GLuint program = glCreateProgram();
    glAttachShader(program, compile(GL_VERTEX_SHADER, vertex_shader));
    glAttachShader(program, compile(GL_GEOMETRY_SHADER, geometry_shader));
    glAttachShader(program, compile(GL_FRAGMENT_SHADER, fragment_shader));
    glLinkProgram(program);
    GLint linked = 0;
    glGetProgramiv(program, GL_LINK_STATUS, &linked);
    if (!linked) throw Failure("shader program does not link");
    glUseProgram(program);
    auto vec3 = [&](const char* name, const json& v) {
        glUniform3f(glGetUniformLocation(program, name), v.at(0).get<float>(), v.at(1).get<float>(),
                    v.at(2).get<float>());
    };
    vec3("camera", camera.at("position"));
    vec3("right", camera.at("right"));
    vec3("up", camera.at("up"));
    vec3("forward", camera.at("forward"));
    glUniform1f(glGetUniformLocation(program, "tan_half"), camera.at("tan_half_vfov").get<float>());
    glUniform1f(glGetUniformLocation(program, "aspect"),
                static_cast<float>(width) / static_cast<float>(height));
    glUniform1f(glGetUniformLocation(program, "near"), 1e-4f * scene.radius);
    return program;
}

// Vertex data: one buffer per attribute, one vertex per triangle corner.
void upload_vertices(const Scene& scene) {
    GLuint vao = 0, buffers[4];
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glGenBuffers(4, buffers);
    auto attribute = [&](int location, const void* data, std::size_t bytes, int size,
                         bool integer) {
        glBindBuffer(GL_ARRAY_BUFFER, buffers[location]);
        glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(bytes), data, GL_STATIC_DRAW);
        if (integer)
            glVertexAttribIPointer(location, size, GL_INT, 0, nullptr);
        else
            glVertexAttribPointer(location, size, GL_FLOAT, GL_FALSE, 0, nullptr);
        glEnableVertexAttribArray(location);
    };
    attribute(0, scene.position.data(), scene.position.size() * sizeof(float), 3, false);
    attribute(1, scene.normal.data(), scene.normal.size() * sizeof(float), 3, false);
    attribute(2, scene.uv.data(), scene.uv.size() * sizeof(float), 2, false);
    attribute(3, scene.material.data(), scene.material.size() * sizeof(int), 1, true);
}

// Textures (RGB32F, bilinear, repeat; the PFM's bottom row is OpenGL's row 0 = v 0), sampled
// from texture unit 0.
std::vector<GLuint> upload_textures(const Scene& scene, GLuint program) {
    std::vector<GLuint> gl_textures(scene.textures.size());
    if (!gl_textures.empty())
        glGenTextures(static_cast<GLsizei>(gl_textures.size()), gl_textures.data());
    for (std::size_t t = 0; t < scene.textures.size(); ++t) {
        glBindTexture(GL_TEXTURE_2D, gl_textures[t]);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB32F, scene.textures[t].width, scene.textures[t].height,
                     0, GL_RGB, GL_FLOAT, scene.textures[t].rgb.data());
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    }
    glUniform1i(glGetUniformLocation(program, "albedo_texture"), 0);
    return gl_textures;
}

// Draw in file order, one draw per run of triangles with the same material (its albedo and
// texture are uniforms); the run's first triangle index offsets gl_PrimitiveID.
void draw(const Scene& scene, GLuint program, const std::vector<GLuint>& gl_textures) {
    const std::size_t triangles = scene.position.size() / 9;
    std::size_t first = 0;
    while (first < triangles) {
        const int m = scene.material[3 * first];
        std::size_t end = first;
        while (end < triangles && scene.material[3 * end] == m) ++end;
        const Material& material = scene.materials.at(static_cast<std::size_t>(m));
        glUniform3f(glGetUniformLocation(program, "albedo"), material.albedo[0], material.albedo[1],
                    material.albedo[2]);
        glUniform1i(glGetUniformLocation(program, "textured"), material.texture >= 0);
        if (material.texture >= 0) {
            glActiveTexture(GL_TEXTURE0);
            glBindTexture(GL_TEXTURE_2D, gl_textures[static_cast<std::size_t>(material.texture)]);
        }
        glUniform1i(glGetUniformLocation(program, "first_primitive"), static_cast<GLint>(first));
        glDrawArrays(GL_TRIANGLES, static_cast<GLint>(3 * first),
                     static_cast<GLsizei>(3 * (end - first)));
        first = end;
    }
    glFinish();
    check_gl("draw");
}

// Read back: bottom row first, which is PFM's order; one PFM per attachment.
void read_back(int width, int height, const std::string& out_prefix) {
    for (int k = 0; k < attachment_count; ++k) {
        const Attachment& a = attachments[k];
        const int read_channels = a.format == GL_RGBA ? 4 : 1;
        std::vector<float> pixels(static_cast<std::size_t>(width) * height * a.channels);
        glReadBuffer(GL_COLOR_ATTACHMENT0 + k);
        if (a.type == GL_INT) {
            std::vector<GLint> ids(static_cast<std::size_t>(width) * height);
            glReadPixels(0, 0, width, height, a.format, a.type, ids.data());
            for (std::size_t p = 0; p < ids.size(); ++p) pixels[p] = static_cast<float>(ids[p]);
        } else {
            std::vector<float> raw(static_cast<std::size_t>(width) * height * read_channels);
            glReadPixels(0, 0, width, height, a.format, a.type, raw.data());
            for (std::size_t p = 0; p < static_cast<std::size_t>(width) * height; ++p)
                for (int c = 0; c < a.channels; ++c)
                    pixels[p * a.channels + c] = raw[p * read_channels + c];
        }
        check_gl("read back");
        fovref_client::write_pfm(out_prefix + a.name + ".pfm", width, height, a.channels, pixels);
    }
}

void render_frame(const Scene& scene, const json& camera, int width, int height,
                  const std::string& out_prefix) {
    make_framebuffer(width, height);
    clear_and_set_state(width, height);
    const GLuint program = make_program(scene, camera, width, height);
    upload_vertices(scene);
    const std::vector<GLuint> gl_textures = upload_textures(scene, program);
    draw(scene, program, gl_textures);
    read_back(width, height, out_prefix);
}

}  // namespace

// An OpenGL 4.5 core context on EGL's surfaceless platform (EGL_MESA_platform_surfaceless): no
// display and no window; the client draws into its framebuffer's textures.
struct Context {
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLContext context = EGL_NO_CONTEXT;
    Context() {
        const auto get_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
            eglGetProcAddress("eglGetPlatformDisplayEXT"));
        if (!get_display) throw Failure("EGL: no eglGetPlatformDisplayEXT");
        display = get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        EGLint major = 0, minor = 0;
        if (display == EGL_NO_DISPLAY || !eglInitialize(display, &major, &minor))
            throw Failure("EGL: no surfaceless display (Mesa's EGL: Debian's libegl-mesa0)");
        if (!eglBindAPI(EGL_OPENGL_API)) throw Failure("EGL: no OpenGL API");
        const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                     4,
                                     EGL_CONTEXT_MINOR_VERSION,
                                     5,
                                     EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                     EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                     EGL_NONE};
        context = eglCreateContext(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
        if (context == EGL_NO_CONTEXT)
            throw Failure("EGL: cannot create an OpenGL 4.5 core context");
        if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context))
            throw Failure("EGL: cannot make the context current");
    }
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;
    ~Context() {
        eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(display, context);
        eglTerminate(display);
    }
};

int main(int argc, char** argv) {
    if (argc != 3 || std::strcmp(argv[1], "--help") == 0) {
        std::fprintf(stderr,
                     "usage: gl_gbuffer BUNDLE OUT_DIR\n"
                     "  renders the G-buffer of a fovref bundle exported with --with-scene\n"
                     "  (fovref golden export CASE BUNDLE --param fill_rule=gl --with-scene)\n"
                     "  with OpenGL 4.5 (EGL, Mesa's surfaceless platform) into "
                     "OUT_DIR/f000_<buffer>.pfm\n");
        return 2;
    }
    const std::string bundle = argv[1], out = argv[2];
    try {
        const json manifest = json::parse(fovref_client::read_text(bundle + "/manifest.json"));
        if (!manifest.contains("scene_export"))
            throw Failure(bundle + "/manifest.json: no scene_export (export with --with-scene)");
        const json& c = manifest.at("case");
        const int width = c.at("width").get<int>(), height = c.at("height").get<int>();
        const json params = c.value("params", json::object());
        if (params.value("fill_rule", "d3d") != "gl")
            std::fprintf(stderr,
                         "gl_gbuffer: note: the bundle uses fill_rule %s; OpenGL's is 'gl' "
                         "(export with --param fill_rule=gl for the same edges)\n",
                         params.value("fill_rule", "d3d").c_str());
        const std::string scene_json = manifest.at("scene_export").get<std::string>();
        const std::string scene_dir =
            bundle + "/" + scene_json.substr(0, scene_json.find_last_of('/') + 1);
        const Scene scene = load_scene(scene_dir + "scene.obj");
        std::error_code ec;
        std::filesystem::create_directories(out, ec);
        if (ec) throw Failure(out + ": cannot create directory: " + ec.message());

        const Context context;
        std::fprintf(stderr, "gl_gbuffer: %s, %s; %zu triangles, %dx%d\n",
                     reinterpret_cast<const char*>(glGetString(GL_RENDERER)),
                     reinterpret_cast<const char*>(glGetString(GL_VERSION)),
                     scene.position.size() / 9, width, height);
        for (const json& frame : manifest.at("frames")) {
            char prefix[32];
            std::snprintf(prefix, sizeof prefix, "/f%03d_", frame.at("frame").get<int>());
            render_frame(scene, frame.at("camera"), width, height, out + prefix);
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "gl_gbuffer: %s\n", e.what());
        return 2;
    }
    return 0;
}
