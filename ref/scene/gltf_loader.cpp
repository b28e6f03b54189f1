// glTF 2.0 scenes (.gltf + .bin, .glb) by Debian's tinygltf 2.7 (docs/gltf.md).
//
// tinygltf parses the JSON (nlohmann::json), decodes data: URIs and reads external buffers; it
// checks little beyond the JSON's shape. Everything it hands over is checked here before it is
// used: every index into another array, every accessor against its bufferView and every
// bufferView against the bytes its buffer really holds, component types and counts, index values
// against the vertex count, and every number for being finite. Each violation throws
// fovref::Error "file: meshes[2].primitives[0]: accessor 5: ...". Where tinygltf itself can be
// led to read out of bounds, the input is checked before it gets there:
//  - the .glb container (tinygltf 2.7 accepts a BIN chunk that ends up to 8 bytes past the
//    file) is validated here first;
//  - image bytes from a bufferView (tinygltf 2.7 forms &buffer[byteOffset] unchecked before it
//    calls the image callback: the pointer is formed out of range for a bad byteOffset, though
//    never read) are never read through tinygltf's pointer: the image callback keeps only data:
//    URI bytes, and bufferView images are cut out of the buffer here, bounds-checked; external
//    image files are read here (percent-decoded relative to the .gltf), so their lookup is ours.
//  - file access goes through our callbacks: paths relative to the .gltf's directory only
//    (tinygltf would also try the current directory), read by read_file with its size limit,
//    never written.
// tinygltf's own std::exception (e.g. std::vector::at on an empty data: URI) becomes an Error.
//
// Numbers in the JSON are read by nlohmann::json as binary64 (strtod, correctly rounded) and
// rounded once more to binary32 here; binary data (positions, normals, uv) is binary32 as stored.
#include "ref/scene/gltf_loader.h"
#include "ref/scene/mesh_builder.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "ref/core/error.h"
#include "ref/core/json_locator.h"
#include "ref/core/limits.h"
#include "ref/image/image_io.h"

namespace fovref {

namespace {

static_assert(std::endian::native == std::endian::little,
              "glTF binary data is little-endian; the reader copies it as it is");

// A quaternion whose squared length is within this of 1 is used as written.
constexpr float unit_length_tolerance = 1e-6f;
// 180 / pi rounded to binary32 (a constant multiply, no libm).
constexpr float degrees_per_radian = 57.2957795130823208768f;
constexpr std::size_t max_listed_places = 5;

std::string at_index(const char* array, std::size_t index) {
    return std::string(array) + "[" + std::to_string(index) + "]";
}

// ---- Files, URIs, the .glb container --------------------------------------------------------

// Percent-decoding of a URI reference (RFC 3986 %XX; '+' stays '+'). A '%' not followed by two
// hex digits is kept as it is.
std::string percent_decode(const std::string& uri) {
    const auto hex = [](char c) -> int {
        if (c >= '0' && c <= '9') return c - '0';
        if (c >= 'a' && c <= 'f') return c - 'a' + 10;
        if (c >= 'A' && c <= 'F') return c - 'A' + 10;
        return -1;
    };
    std::string out;
    for (std::size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size() && hex(uri[i + 1]) >= 0 && hex(uri[i + 2]) >= 0) {
            out += static_cast<char>(hex(uri[i + 1]) * 16 + hex(uri[i + 2]));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

std::uint32_t load_u32_le(const std::string& bytes, std::size_t at) {
    std::uint32_t value = 0;
    std::memcpy(&value, bytes.data() + at, 4);
    return value;
}

// Checks the .glb container (header, JSON chunk, optional BIN chunk) and returns the number of
// bytes that belong to it (the header's length).
std::size_t check_glb(const std::string& path, const std::string& bytes) {
    if (bytes.size() < 20)
        throw Error(path + ": truncated .glb (" + std::to_string(bytes.size()) +
                    " bytes, the header and JSON chunk header need 20)");
    const std::uint32_t version = load_u32_le(bytes, 4);
    const std::uint32_t length = load_u32_le(bytes, 8);
    if (version != 2)
        throw Error(path + ": .glb version " + std::to_string(version) + " (only 2 is read)");
    if (length > bytes.size())
        throw Error(path + ": truncated .glb: the header says " + std::to_string(length) +
                    " bytes, the file has " + std::to_string(bytes.size()));
    if (length < 20) throw Error(path + ": .glb header length " + std::to_string(length) + " < 20");
    const std::uint64_t json_length = load_u32_le(bytes, 12);
    if (load_u32_le(bytes, 16) != 0x4E4F534Au)
        throw Error(path + ": .glb: the first chunk is not JSON");
    if (json_length == 0 || 20 + json_length > length)
        throw Error(path + ": truncated .glb: the JSON chunk of " + std::to_string(json_length) +
                    " bytes does not fit in " + std::to_string(length));
    const std::uint64_t bin_at = 20 + json_length;
    if (bin_at < length) {
        if (bin_at + 8 > length) throw Error(path + ": truncated .glb: a chunk header is cut off");
        const std::uint64_t bin_length = load_u32_le(bytes, static_cast<std::size_t>(bin_at));
        if (bin_at + 8 + bin_length > length)
            throw Error(path + ": truncated .glb: the BIN chunk of " + std::to_string(bin_length) +
                        " bytes does not fit in " + std::to_string(length));
        if (load_u32_le(bytes, static_cast<std::size_t>(bin_at + 4)) != 0x004E4942u)
            throw Error(path + ": .glb: the second chunk is not BIN");
    }
    return length;
}

// tinygltf converts "extras" and "extensions" recursively (and nlohmann::json nests as deep as
// the text): JSON nested deeper than this is refused before it is parsed, so that a hostile
// file cannot exhaust the stack.
constexpr int max_json_depth = 64;

// File access for tinygltf: paths that tinygltf joined to the .gltf's `directory` only (its
// fallback search of the current directory is refused; "../" in a URI is allowed, as for OBJ
// paths), read with read_file's limits, nothing written.
struct FsContext {
    std::string directory;  ///< absolute, without a trailing '/'
};

bool fs_file_exists(const std::string& path, void* user) {
    const auto* context = static_cast<const FsContext*>(user);
    const std::string prefix =
        context->directory.back() == '/' ? context->directory : context->directory + "/";
    if (path.compare(0, prefix.size(), prefix) != 0) return false;
    std::error_code ec;
    return std::filesystem::is_regular_file(path, ec);
}

std::string fs_expand_path(const std::string& path, void*) { return path; }

bool fs_read_file(std::vector<unsigned char>* out, std::string* err, const std::string& path,
                  void* user) {
    if (!fs_file_exists(path, user)) {
        if (err) *err += "not found";
        return false;
    }
    try {
        const std::string bytes = read_file(path);
        out->assign(bytes.begin(), bytes.end());
        return true;
    } catch (const Error& e) {
        if (err) *err += e.what();
        return false;
    }
}

bool fs_write_file(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err) *err += "fovref does not write through tinygltf";
    return false;
}

// tinygltf's image callback: keeps the bytes of data: URI images only (see the top of the
// file); nothing is decoded here.
bool keep_image_bytes(tinygltf::Image* image, const int index, std::string*, std::string*, int, int,
                      const unsigned char* bytes, int size, void* user) {
    if (image->bufferView >= 0 || !image->uri.empty()) return true;
    if (bytes != nullptr && size > 0 && index >= 0)
        (*static_cast<std::map<int, std::string>*>(user))[index] =
            std::string(reinterpret_cast<const char*>(bytes), static_cast<std::size_t>(size));
    return true;
}

// tinygltf's message text on one line: lines joined with "; ".
std::string one_line(const std::string& text) {
    std::string out;
    std::size_t start = 0;
    while (start < text.size()) {
        std::size_t end = text.find('\n', start);
        if (end == std::string::npos) end = text.size();
        std::string line = text.substr(start, end - start);
        while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
        if (!line.empty()) out += (out.empty() ? "" : "; ") + line;
        start = end + 1;
    }
    return out;
}

// ---- The loader's state -----------------------------------------------------------------------

struct Loader {
    Scene& scene;
    const std::string& path;  ///< as given, prefixes every message
    std::string directory;    ///< of the file, for external images
    std::string file_name;    ///< the last path component
    std::string canonical;    ///< cache keys of embedded images
    tinygltf::Model model;
    std::map<int, std::string> data_uri_images;
    TextureCache& cache;
    GltfContents contents;
    /// Unsupported feature text ("normalTexture (ignored)") -> places ("materials[2]").
    std::map<std::string, std::vector<std::string>> unsupported;
    std::vector<int> material_index;  ///< glTF material -> scene material (-1 until interned)
    int default_material = -1;
    std::string default_name;  ///< "gltf-default", made unique among the file's names
    std::int64_t dropped_here = 0;
    std::map<int, std::int64_t> ignored_modes;  ///< primitive mode -> primitives
    std::vector<bool> node_visited;

    Loader(Scene& scene_, const std::string& path_, TextureCache& cache_)
        : scene(scene_), path(path_), cache(cache_) {}

    Error error(const std::string& where, const std::string& message) const {
        return Error(path + ": " + (where.empty() ? "" : where + ": ") + message);
    }
    void note(const std::string& feature, const std::string& where) {
        unsupported[feature].push_back(where);
    }
};

// Throws "<file>: <where>: <what> <index> does not exist (the file has <count>)" unless
// 0 <= index < count: the check of every index into one of the file's arrays.
void check_exists(const Loader& loader, int index, std::size_t count, const char* what,
                  const std::string& where) {
    if (index < 0 || static_cast<std::size_t>(index) >= count)
        throw loader.error(where, std::string(what) + " " + std::to_string(index) +
                                      " does not exist (the file has " + std::to_string(count) +
                                      ")");
}

// ---- Numbers from the JSON --------------------------------------------------------------------

float json_float(const Loader& loader, double value, const std::string& where, const char* what) {
    const float f = static_cast<float>(value);
    if (!std::isfinite(f))
        throw loader.error(where, std::string(what) + " is not a finite binary32 number");
    return f;
}

float json_unit(const Loader& loader, double value, const std::string& where, const char* what) {
    const float f = json_float(loader, value, where, what);
    if (!(f >= 0.0f && f <= 1.0f))
        throw loader.error(where,
                           std::string(what) + " must be in [0, 1], got " + check_value_text(f));
    return f;
}

// ---- Accessors --------------------------------------------------------------------------------

int component_bytes(int component_type) {
    switch (component_type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
        case TINYGLTF_COMPONENT_TYPE_INT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
        default: return 0;
    }
}

const char* component_name(int component_type) {
    switch (component_type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE: return "BYTE";
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return "UNSIGNED_BYTE";
        case TINYGLTF_COMPONENT_TYPE_SHORT: return "SHORT";
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return "UNSIGNED_SHORT";
        case TINYGLTF_COMPONENT_TYPE_INT: return "INT";
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return "UNSIGNED_INT";
        case TINYGLTF_COMPONENT_TYPE_FLOAT: return "FLOAT";
        default: return "an unknown component type";
    }
}

int type_components(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR: return 1;
        case TINYGLTF_TYPE_VEC2: return 2;
        case TINYGLTF_TYPE_VEC3: return 3;
        case TINYGLTF_TYPE_VEC4: return 4;
        case TINYGLTF_TYPE_MAT2: return 4;
        case TINYGLTF_TYPE_MAT3: return 9;
        case TINYGLTF_TYPE_MAT4: return 16;
        default: return 0;
    }
}

const char* type_name(int components) {
    switch (components) {
        case 1: return "SCALAR";
        case 2: return "VEC2";
        case 3: return "VEC3";
        default: return "VEC4";
    }
}

// Where an accessor's elements lie: element i starts at data + i * stride.
struct ElementBytes {
    const unsigned char* data = nullptr;
    std::size_t stride = 0;
    std::size_t count = 0;
};

// The bytes of a bufferView, checked against what its buffer really holds.
struct ViewBytes {
    const unsigned char* data = nullptr;
    std::size_t length = 0;
    std::size_t byte_stride = 0;  ///< 0 = tightly packed
};

ViewBytes view_bytes(const Loader& loader, int view_index, const std::string& where) {
    const tinygltf::Model& model = loader.model;
    check_exists(loader, view_index, model.bufferViews.size(), "bufferView", where);
    const tinygltf::BufferView& view = model.bufferViews[static_cast<std::size_t>(view_index)];
    const std::string view_where = where + ": bufferView " + std::to_string(view_index);
    check_exists(loader, view.buffer, model.buffers.size(), "buffer", view_where);
    const std::vector<unsigned char>& data =
        model.buffers[static_cast<std::size_t>(view.buffer)].data;
    if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset)
        throw loader.error(view_where, "bytes [" + std::to_string(view.byteOffset) + ", " +
                                           std::to_string(view.byteOffset) + " + " +
                                           std::to_string(view.byteLength) +
                                           ") lie outside buffer " + std::to_string(view.buffer) +
                                           " (" + std::to_string(data.size()) + " bytes)");
    return {data.data() + view.byteOffset, view.byteLength, view.byteStride};
}

// Accessor `index` checked for its type (`components` per element), its component type (one of
// `allowed`), and its elements lying inside its bufferView.
ElementBytes accessor_elements(const Loader& loader, int index, int components,
                               std::initializer_list<int> allowed, bool need_normalized,
                               const std::string& where_prefix, const char* role) {
    const tinygltf::Model& model = loader.model;
    const std::string where =
        where_prefix + ": accessor " + std::to_string(index) + " (" + role + ")";
    if (index < 0 || static_cast<std::size_t>(index) >= model.accessors.size())
        throw loader.error(where, "does not exist (the file has " +
                                      std::to_string(model.accessors.size()) + " accessors)");
    const tinygltf::Accessor& accessor = model.accessors[static_cast<std::size_t>(index)];
    if (type_components(accessor.type) != components)
        throw loader.error(where, std::string("must be ") + type_name(components));
    const int bytes = component_bytes(accessor.componentType);
    const bool allowed_type =
        std::find(allowed.begin(), allowed.end(), accessor.componentType) != allowed.end();
    if (!allowed_type || bytes == 0) {
        std::string names;
        for (int type : allowed)
            names += std::string(names.empty() ? "" : " or ") + component_name(type);
        throw loader.error(
            where, std::string("componentType ") + std::to_string(accessor.componentType) + " (" +
                       component_name(accessor.componentType) + "), expected " + names);
    }
    if (need_normalized && accessor.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT &&
        !accessor.normalized)
        throw loader.error(where, std::string("integer ") + component_name(accessor.componentType) +
                                      " values must be normalized");
    if (accessor.sparse.isSparse)
        throw loader.error(where, "is sparse (sparse accessors are not supported)");
    if (accessor.bufferView < 0)
        throw loader.error(where, "has no bufferView (accessors without data are not supported)");
    const ViewBytes view = view_bytes(loader, accessor.bufferView, where);
    const std::size_t element = static_cast<std::size_t>(components * bytes);
    const std::size_t stride = view.byte_stride == 0 ? element : view.byte_stride;
    if (stride < element)
        throw loader.error(where, "bufferView " + std::to_string(accessor.bufferView) +
                                      " has byteStride " + std::to_string(stride) +
                                      ", less than the element size " + std::to_string(element));
    ElementBytes out;
    out.stride = stride;
    out.count = accessor.count;
    if (accessor.count == 0) return out;
    // offset + stride * (count - 1) + element <= length, without overflow.
    const bool fits = accessor.byteOffset <= view.length &&
                      element <= view.length - accessor.byteOffset &&
                      accessor.count - 1 <= (view.length - accessor.byteOffset - element) / stride;
    if (!fits)
        throw loader.error(
            where, std::to_string(accessor.count) + " elements of " + std::to_string(element) +
                       " bytes, " + std::to_string(stride) + " apart, from byteOffset " +
                       std::to_string(accessor.byteOffset) + " do not fit in bufferView " +
                       std::to_string(accessor.bufferView) + " (" + std::to_string(view.length) +
                       " bytes)");
    out.data = view.data + accessor.byteOffset;
    return out;
}

int accessor_component_type(const Loader& loader, int index) {
    return loader.model.accessors[static_cast<std::size_t>(index)].componentType;
}

// Float attribute values, `components` per element: FLOAT as stored (each finite), normalized
// UNSIGNED_BYTE / UNSIGNED_SHORT as value / 255 or value / 65535 (correctly rounded division).
std::vector<float> read_float_attribute(const Loader& loader, int index, int components,
                                        std::initializer_list<int> allowed,
                                        const std::string& where, const char* role) {
    const ElementBytes elements =
        accessor_elements(loader, index, components, allowed, true, where, role);
    const int type = accessor_component_type(loader, index);
    std::vector<float> values(elements.count * static_cast<std::size_t>(components));
    for (std::size_t i = 0; i < elements.count; ++i) {
        const unsigned char* element = elements.data + i * elements.stride;
        for (int c = 0; c < components; ++c) {
            float value = 0.0f;
            if (type == TINYGLTF_COMPONENT_TYPE_FLOAT) {
                std::memcpy(&value, element + 4 * c, 4);
                if (!std::isfinite(value))
                    throw loader.error(
                        where + ": accessor " + std::to_string(index) + " (" + role + ")",
                        "element " + std::to_string(i) + " component " + std::to_string(c) +
                            " is NaN or infinite");
            } else if (type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
                value = static_cast<float>(element[c]) / 255.0f;
            } else {
                std::uint16_t v = 0;
                std::memcpy(&v, element + 2 * c, 2);
                value = static_cast<float>(v) / 65535.0f;
            }
            values[i * static_cast<std::size_t>(components) + static_cast<std::size_t>(c)] = value;
        }
    }
    return values;
}

// Index values (UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT), each < vertex_count.
std::vector<std::uint32_t> read_indices(const Loader& loader, int index, std::size_t vertex_count,
                                        const std::string& where) {
    const ElementBytes elements = accessor_elements(
        loader, index, 1,
        {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
         TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT},
        false, where, "indices");
    const int type = accessor_component_type(loader, index);
    std::vector<std::uint32_t> values(elements.count);
    for (std::size_t i = 0; i < elements.count; ++i) {
        const unsigned char* element = elements.data + i * elements.stride;
        std::uint32_t value = 0;
        if (type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
            value = element[0];
        } else if (type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
            std::uint16_t v = 0;
            std::memcpy(&v, element, 2);
            value = v;
        } else {
            std::memcpy(&value, element, 4);
        }
        if (value >= vertex_count)
            throw loader.error(where + ": accessor " + std::to_string(index) + " (indices)",
                               "index " + std::to_string(i) + " is " + std::to_string(value) +
                                   ", not below the vertex count " + std::to_string(vertex_count));
        values[i] = value;
    }
    return values;
}

// ---- Textures and materials -------------------------------------------------------------------

std::string image_extension(const std::string& bytes) {
    const std::string format = image_format_of_bytes(bytes);
    if (format == "png") return ".png";
    if (format == "jpeg") return ".jpg";
    if (format == "bmp") return ".bmp";
    return "";
}

// The scene texture of glTF texture `index` (a baseColorTexture), or -1 when it has no image
// fovref can use (listed as unsupported).
int base_color_texture(Loader& loader, const tinygltf::TextureInfo& info,
                       const std::string& where) {
    const tinygltf::Model& model = loader.model;
    if (info.index < 0 || static_cast<std::size_t>(info.index) >= model.textures.size())
        throw loader.error(where, "baseColorTexture names texture " + std::to_string(info.index) +
                                      ", which does not exist (the file has " +
                                      std::to_string(model.textures.size()) + ")");
    if (info.texCoord != 0)
        loader.note("baseColorTexture.texCoord " + std::to_string(info.texCoord) +
                        " (TEXCOORD_0 used instead)",
                    where);
    for (const auto& [name, value] : info.extensions) {
        (void)value;
        loader.note("baseColorTexture extension " + name + " (ignored)", where);
    }
    const std::string texture_where = at_index("textures", static_cast<std::size_t>(info.index));
    const tinygltf::Texture& texture = model.textures[static_cast<std::size_t>(info.index)];
    for (const auto& [name, value] : texture.extensions) {
        (void)value;
        loader.note("texture extension " + name + " (ignored)", texture_where);
    }
    if (texture.sampler >= 0) {
        if (static_cast<std::size_t>(texture.sampler) >= model.samplers.size())
            throw loader.error(texture_where,
                               "sampler " + std::to_string(texture.sampler) + " does not exist");
        const tinygltf::Sampler& sampler =
            model.samplers[static_cast<std::size_t>(texture.sampler)];
        if (sampler.wrapS != TINYGLTF_TEXTURE_WRAP_REPEAT ||
            sampler.wrapT != TINYGLTF_TEXTURE_WRAP_REPEAT)
            loader.note("sampler wrap mode other than REPEAT (sampled with repeat wrap)",
                        at_index("samplers", static_cast<std::size_t>(texture.sampler)));
        const auto linear = [](int filter) {
            return filter == -1 || filter == TINYGLTF_TEXTURE_FILTER_LINEAR;
        };
        if (!linear(sampler.minFilter) || !linear(sampler.magFilter))
            loader.note("sampler filter other than LINEAR (sampled bilinearly, without mipmaps)",
                        at_index("samplers", static_cast<std::size_t>(texture.sampler)));
    }
    if (texture.source < 0) {
        loader.note("texture without a source image (no texture)", texture_where);
        return -1;
    }
    check_exists(loader, texture.source, model.images.size(), "source image", texture_where);
    const std::size_t image_index = static_cast<std::size_t>(texture.source);
    const tinygltf::Image& image = model.images[image_index];
    const std::string image_where = at_index("images", image_index);
    const std::string referenced = loader.path + ": " + image_where;
    if (image.bufferView >= 0) {
        const ViewBytes view = view_bytes(loader, image.bufferView, image_where);
        const std::string bytes(reinterpret_cast<const char*>(view.data), view.length);
        const std::string name = std::filesystem::path(loader.file_name).stem().string() +
                                 "-image" + std::to_string(image_index) + image_extension(bytes);
        return load_texture_bytes(loader.scene, bytes, name, loader.canonical + "#" + image_where,
                                  loader.cache, referenced);
    }
    if (!image.uri.empty()) {
        const std::string name = percent_decode(image.uri);
        const std::string file = loader.directory.empty()
                                     ? name
                                     : (std::filesystem::path(loader.directory) / name).string();
        std::error_code ec;
        if (!std::filesystem::is_regular_file(file, ec))
            throw loader.error(image_where,
                               "image file '" + name + "' not found (looked for " + file + ")");
        const std::string key = std::filesystem::weakly_canonical(file, ec).string();
        auto cached = loader.cache.find(key);
        if (cached != loader.cache.end()) return cached->second;
        return load_texture_bytes(loader.scene, read_file(file), name, key, loader.cache,
                                  referenced);
    }
    auto embedded = loader.data_uri_images.find(static_cast<int>(image_index));
    if (embedded == loader.data_uri_images.end())
        throw loader.error(image_where, "has no image data");
    const std::string name = std::filesystem::path(loader.file_name).stem().string() + "-image" +
                             std::to_string(image_index) + image_extension(embedded->second);
    return load_texture_bytes(loader.scene, embedded->second, name,
                              loader.canonical + "#" + image_where, loader.cache, referenced);
}

// glTF's metallic-roughness parameters in fovref's material model (docs/gltf.md).
Material pbr_material(const std::string& name, glm::vec3 base, float metallic, float roughness,
                      glm::vec3 emission) {
    Material material;
    material.name = name;
    const float dielectric = 1.0f - metallic;
    material.albedo = base * dielectric;
    material.specular = glm::vec3(0.04f * dielectric) + base * metallic;
    material.roughness = roughness;
    material.emission = emission;
    return material;
}

// Names for the file's materials: the glTF name when it is non-empty and unique in the file,
// else "<name>#<index>", or "material#<index>" for an unnamed one; a generated name that some
// other material already has gets "#<index>" appended until it is free.
std::vector<std::string> material_names(const tinygltf::Model& model, std::set<std::string>& used) {
    std::map<std::string, int> counts;
    for (const tinygltf::Material& material : model.materials)
        if (!material.name.empty()) ++counts[material.name];
    std::vector<std::string> names(model.materials.size());
    for (std::size_t m = 0; m < model.materials.size(); ++m)
        if (!model.materials[m].name.empty() && counts[model.materials[m].name] == 1) {
            names[m] = model.materials[m].name;
            used.insert(names[m]);
        }
    for (std::size_t m = 0; m < model.materials.size(); ++m) {
        if (!names[m].empty()) continue;
        const std::string suffix = "#" + std::to_string(m);
        std::string name =
            (model.materials[m].name.empty() ? std::string("material") : model.materials[m].name) +
            suffix;
        while (used.count(name) != 0) name += suffix;
        used.insert(name);
        names[m] = name;
    }
    return names;
}

void convert_materials(Loader& loader) {
    const tinygltf::Model& model = loader.model;
    std::set<std::string> used;
    const std::vector<std::string> names = material_names(model, used);
    loader.material_index.assign(model.materials.size(), -1);
    for (std::size_t m = 0; m < model.materials.size(); ++m) {
        const tinygltf::Material& source = model.materials[m];
        const std::string where = at_index("materials", m);
        const tinygltf::PbrMetallicRoughness& pbr = source.pbrMetallicRoughness;
        glm::vec3 base(1.0f);
        if (!pbr.baseColorFactor.empty()) {
            if (pbr.baseColorFactor.size() != 4)
                throw loader.error(where, "baseColorFactor needs 4 numbers");
            for (int c = 0; c < 3; ++c)
                base[c] = json_unit(loader, pbr.baseColorFactor[static_cast<std::size_t>(c)], where,
                                    "baseColorFactor");
            if (json_unit(loader, pbr.baseColorFactor[3], where, "baseColorFactor") < 1.0f)
                loader.note("baseColorFactor alpha below 1 (rendered opaque)", where);
        }
        const float metallic = json_unit(loader, pbr.metallicFactor, where, "metallicFactor");
        const float roughness = json_unit(loader, pbr.roughnessFactor, where, "roughnessFactor");
        glm::vec3 emissive(0.0f);
        if (!source.emissiveFactor.empty()) {
            if (source.emissiveFactor.size() != 3)
                throw loader.error(where, "emissiveFactor needs 3 numbers");
            for (int c = 0; c < 3; ++c)
                emissive[c] = json_unit(loader, source.emissiveFactor[static_cast<std::size_t>(c)],
                                        where, "emissiveFactor");
        }
        float strength = 1.0f;
        for (const auto& [name, value] : source.extensions) {
            if (name != "KHR_materials_emissive_strength") {
                loader.note("material extension " + name + " (ignored)", where);
                continue;
            }
            if (!value.IsObject())
                throw loader.error(where, "KHR_materials_emissive_strength is not an object");
            if (value.Has("emissiveStrength")) {
                const tinygltf::Value& number = value.Get("emissiveStrength");
                if (!number.IsNumber())
                    throw loader.error(where, "emissiveStrength is not a number");
                strength =
                    json_float(loader, number.GetNumberAsDouble(), where, "emissiveStrength");
                if (!(strength >= 0.0f)) throw loader.error(where, "emissiveStrength must be >= 0");
            }
        }
        for (const auto& [name, value] : pbr.extensions) {
            (void)value;
            loader.note("pbrMetallicRoughness extension " + name + " (ignored)", where);
        }
        const glm::vec3 emission = emissive * strength;
        if (!std::isfinite(emission.x) || !std::isfinite(emission.y) || !std::isfinite(emission.z))
            throw loader.error(where, "emissiveFactor * emissiveStrength is not finite");
        Material material = pbr_material(names[m], base, metallic, roughness, emission);
        if (pbr.baseColorTexture.index >= 0)
            material.texture = base_color_texture(loader, pbr.baseColorTexture, where);
        if (pbr.metallicRoughnessTexture.index >= 0)
            loader.note(
                "metallicRoughnessTexture (ignored: metallicFactor and roughnessFactor used)",
                where);
        if (source.normalTexture.index >= 0)
            loader.note("normalTexture (ignored: vertex normals used)", where);
        if (source.occlusionTexture.index >= 0) loader.note("occlusionTexture (ignored)", where);
        if (source.emissiveTexture.index >= 0)
            loader.note("emissiveTexture (ignored: emissiveFactor used)", where);
        if (!source.alphaMode.empty() && source.alphaMode != "OPAQUE")
            loader.note("alphaMode " + source.alphaMode + " (rendered opaque)", where);
        if (!source.doubleSided)
            loader.note("doubleSided false (rendered two-sided, as every fovref surface)", where);
        loader.material_index[m] =
            intern_material(loader.scene, material, loader.path + ": " + where, loader.cache);
    }
    // The default material's name, should a primitive need it.
    std::string default_name = "gltf-default";
    while (used.count(default_name) != 0) default_name += "#";
    loader.default_name = default_name;
}

// ---- Nodes ------------------------------------------------------------------------------------

// Rotation matrix of the quaternion (x, y, z, w), normalised first unless |q|^2 is within
// unit_length_tolerance of 1; multiplies and adds only (and one sqrt when normalising).
glm::mat3 quaternion_matrix(const Loader& loader, const std::vector<double>& q,
                            const std::string& where) {
    float x = json_float(loader, q[0], where, "rotation");
    float y = json_float(loader, q[1], where, "rotation");
    float z = json_float(loader, q[2], where, "rotation");
    float w = json_float(loader, q[3], where, "rotation");
    const float length2 = x * x + y * y + z * z + w * w;
    if (!(length2 > 0.0f) || !std::isfinite(length2))
        throw loader.error(where, "rotation quaternion is zero or too large");
    if (std::fabs(length2 - 1.0f) > unit_length_tolerance) {
        const float length = std::sqrt(length2);
        x /= length;
        y /= length;
        z /= length;
        w /= length;
    }
    const float xx = x * x, yy = y * y, zz = z * z;
    const float xy = x * y, xz = x * z, yz = y * z;
    const float wx = w * x, wy = w * y, wz = w * z;
    glm::mat3 r;  // r[column][row]
    r[0][0] = 1.0f - 2.0f * (yy + zz);
    r[0][1] = 2.0f * (xy + wz);
    r[0][2] = 2.0f * (xz - wy);
    r[1][0] = 2.0f * (xy - wz);
    r[1][1] = 1.0f - 2.0f * (xx + zz);
    r[1][2] = 2.0f * (yz + wx);
    r[2][0] = 2.0f * (xz + wy);
    r[2][1] = 2.0f * (yz - wx);
    r[2][2] = 1.0f - 2.0f * (xx + yy);
    return r;
}

// The node's local matrix: `matrix` (column-major) when given, else T * R * S.
glm::mat4 local_matrix(const Loader& loader, const tinygltf::Node& node, const std::string& where) {
    glm::mat4 m(1.0f);
    if (!node.matrix.empty()) {
        if (node.matrix.size() != 16) throw loader.error(where, "matrix needs 16 numbers");
        for (int column = 0; column < 4; ++column)
            for (int row = 0; row < 4; ++row)
                m[column][row] =
                    json_float(loader, node.matrix[static_cast<std::size_t>(4 * column + row)],
                               where, "matrix");
        return m;
    }
    if (!node.translation.empty() && node.translation.size() != 3)
        throw loader.error(where, "translation needs 3 numbers");
    if (!node.rotation.empty() && node.rotation.size() != 4)
        throw loader.error(where, "rotation needs 4 numbers");
    if (!node.scale.empty() && node.scale.size() != 3)
        throw loader.error(where, "scale needs 3 numbers");
    glm::vec3 scale(1.0f);
    for (std::size_t c = 0; c < node.scale.size(); ++c)
        scale[static_cast<int>(c)] = json_float(loader, node.scale[c], where, "scale");
    const glm::mat3 rotation =
        node.rotation.empty() ? glm::mat3(1.0f) : quaternion_matrix(loader, node.rotation, where);
    for (int column = 0; column < 3; ++column)
        for (int row = 0; row < 3; ++row) m[column][row] = rotation[column][row] * scale[column];
    for (std::size_t c = 0; c < node.translation.size(); ++c)
        m[3][static_cast<int>(c)] = json_float(loader, node.translation[c], where, "translation");
    return m;
}

int primitive_material(Loader& loader, int material, const std::string& where) {
    if (material >= 0) {
        check_exists(loader, material, loader.material_index.size(), "material", where);
        return loader.material_index[static_cast<std::size_t>(material)];
    }
    if (loader.default_material < 0) {
        // The glTF default material: base colour 1, metallic 1, roughness 1.
        loader.default_material = intern_material(
            loader.scene,
            pbr_material(loader.default_name, glm::vec3(1.0f), 1.0f, 1.0f, glm::vec3(0.0f)),
            loader.path + ": " + where, loader.cache);
    }
    return loader.default_material;
}

// Corner indices of triangle t of a primitive (glTF 2.0 §3.7.2.1): TRIANGLES (v3t, v3t+1,
// v3t+2); TRIANGLE_STRIP (vt, vt+1+t%2, vt+2-t%2); TRIANGLE_FAN (vt+1, vt+2, v0).
void triangle_corners(int mode, std::size_t t, std::size_t (&corner)[3]) {
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        corner[0] = 3 * t;
        corner[1] = 3 * t + 1;
        corner[2] = 3 * t + 2;
    } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        corner[0] = t;
        corner[1] = t + 1 + t % 2;
        corner[2] = t + 2 - t % 2;
    } else {
        corner[0] = t + 1;
        corner[1] = t + 2;
        corner[2] = 0;
    }
}

// The parts of a primitive fovref does not read, each noted once per primitive.
void note_ignored_parts(Loader& loader, const tinygltf::Primitive& primitive,
                        const std::string& where) {
    for (const auto& [name, accessor] : primitive.attributes) {
        (void)accessor;
        if (name != "POSITION" && name != "NORMAL" && name != "TEXCOORD_0")
            loader.note("attribute " + name + " (ignored)", where);
    }
    if (!primitive.targets.empty()) loader.note("morph targets (base mesh used)", where);
    for (const auto& [name, value] : primitive.extensions) {
        (void)value;
        loader.note("primitive extension " + name + " (ignored)", where);
    }
}

// A primitive's vertex attributes: positions (required), normals and uvs (when given, one per
// position).
struct PrimitiveVertices {
    std::vector<float> positions, normals, uvs;
    std::size_t count() const { return positions.size() / 3; }
};

PrimitiveVertices read_vertices(Loader& loader, const tinygltf::Primitive& primitive,
                                const std::string& where) {
    const auto attribute = [&](const char* name) {
        auto it = primitive.attributes.find(name);
        return it == primitive.attributes.end() ? -1 : it->second;
    };
    const int position_accessor = attribute("POSITION");
    if (position_accessor < 0) throw loader.error(where, "has no POSITION attribute");
    PrimitiveVertices v;
    v.positions = read_float_attribute(loader, position_accessor, 3,
                                       {TINYGLTF_COMPONENT_TYPE_FLOAT}, where, "POSITION");
    if (attribute("NORMAL") >= 0) {
        v.normals = read_float_attribute(loader, attribute("NORMAL"), 3,
                                         {TINYGLTF_COMPONENT_TYPE_FLOAT}, where, "NORMAL");
        if (v.normals.size() != v.positions.size())
            throw loader.error(where, "NORMAL has " + std::to_string(v.normals.size() / 3) +
                                          " elements, POSITION " + std::to_string(v.count()));
    }
    if (attribute("TEXCOORD_0") >= 0) {
        v.uvs = read_float_attribute(
            loader, attribute("TEXCOORD_0"), 2,
            {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
             TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT},
            where, "TEXCOORD_0");
        if (v.uvs.size() / 2 != v.count())
            throw loader.error(where, "TEXCOORD_0 has " + std::to_string(v.uvs.size() / 2) +
                                          " elements, POSITION " + std::to_string(v.count()));
    }
    return v;
}

// Triangle t's corners in the world (vertex v of the primitive: indices[corner], or the corner
// itself without indices).
WorldTriangle world_triangle(const PrimitiveVertices& vertices,
                             const std::vector<std::uint32_t>& indices, int mode, std::size_t t,
                             const ObjectToWorld& to_world) {
    std::size_t corner[3];
    triangle_corners(mode, t, corner);
    if (to_world.mirror) std::swap(corner[1], corner[2]);
    const std::vector<float>& p = vertices.positions;
    const std::vector<float>& n = vertices.normals;
    const std::vector<float>& uv = vertices.uvs;
    WorldTriangle tri{};
    for (int c = 0; c < 3; ++c) {
        const std::size_t v = indices.empty() ? corner[c] : indices[corner[c]];
        tri.position[c] = to_world.point(glm::vec3(p[3 * v], p[3 * v + 1], p[3 * v + 2]));
        tri.has_normal[c] = !n.empty();
        if (tri.has_normal[c])
            tri.normal[c] = to_world.normal(glm::vec3(n[3 * v], n[3 * v + 1], n[3 * v + 2]));
        // glTF's v runs down the image, fovref's (OBJ's) up: v' = 1 - v.
        tri.uv[c] = uv.empty() ? glm::vec2(0.0f) : glm::vec2(uv[2 * v], 1.0f - uv[2 * v + 1]);
    }
    return tri;
}

void add_primitive(Loader& loader, const tinygltf::Primitive& primitive, const std::string& where,
                   const ObjectToWorld& to_world) {
    const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
    if (mode >= TINYGLTF_MODE_POINTS && mode <= TINYGLTF_MODE_LINE_STRIP) {
        ++loader.ignored_modes[mode];
        return;
    }
    if (mode > TINYGLTF_MODE_TRIANGLE_FAN)
        throw loader.error(where, "mode " + std::to_string(mode) + " is not a glTF primitive mode");
    const int material = primitive_material(loader, primitive.material, where);
    note_ignored_parts(loader, primitive, where);
    const PrimitiveVertices vertices = read_vertices(loader, primitive, where);
    std::vector<std::uint32_t> indices;
    const bool indexed = primitive.indices >= 0;
    if (indexed) indices = read_indices(loader, primitive.indices, vertices.count(), where);
    const std::size_t corner_count = indexed ? indices.size() : vertices.count();
    if (mode == TINYGLTF_MODE_TRIANGLES && corner_count % 3 != 0)
        throw loader.error(where, std::string(indexed ? "index" : "vertex") + " count " +
                                      std::to_string(corner_count) +
                                      " is not a multiple of 3 (mode TRIANGLES)");
    const std::size_t triangles = mode == TINYGLTF_MODE_TRIANGLES ? corner_count / 3
                                  : corner_count >= 3             ? corner_count - 2
                                                                  : 0;
    SceneLoadStats& stats = loader.scene.load_stats;
    for (std::size_t t = 0; t < triangles; ++t) {
        WorldTriangle tri = world_triangle(vertices, indices, mode, t, to_world);
        if (!append_triangle(loader.scene, tri, material, loader.path) &&
            ++loader.dropped_here <= max_listed_warnings)
            stats.warnings.push_back(loader.path + ": " + where + ": triangle " +
                                     std::to_string(t) + ": zero-area triangle dropped");
    }
}

// A number in an extension object that must be a non-negative integer below `limit`.
int extension_index(const Loader& loader, const tinygltf::Value& value, const char* key,
                    std::size_t limit, const std::string& where) {
    if (!value.IsObject() || !value.Has(key) || !value.Get(key).IsNumber())
        throw loader.error(where, std::string("KHR_lights_punctual needs a number '") + key + "'");
    const double number = value.Get(key).GetNumberAsDouble();
    if (!(number >= 0.0 && number < static_cast<double>(limit)) || std::floor(number) != number)
        throw loader.error(where, std::string("KHR_lights_punctual ") + key + " " +
                                      check_value_text(number) + " does not name one of the " +
                                      std::to_string(limit) + " lights");
    return static_cast<int>(number);
}

void add_camera(Loader& loader, const tinygltf::Node& node, const glm::mat4& world,
                const std::string& where) {
    const tinygltf::Model& model = loader.model;
    check_exists(loader, node.camera, model.cameras.size(), "camera", where);
    const tinygltf::Camera& source = model.cameras[static_cast<std::size_t>(node.camera)];
    const std::string camera_where = at_index("cameras", static_cast<std::size_t>(node.camera));
    if (source.type != "perspective") {
        loader.note(
            "camera type '" + source.type + "' (ignored; only perspective cameras are read)",
            where);
        return;
    }
    if (loader.contents.camera) {
        loader.note("further cameras (ignored; the first perspective camera is used)", where);
        return;
    }
    const float yfov = json_float(loader, source.perspective.yfov, camera_where, "yfov");
    Camera camera;
    camera.vfov_deg = yfov * degrees_per_radian;
    if (!(camera.vfov_deg > 0.0f && camera.vfov_deg < 180.0f))
        throw loader.error(camera_where,
                           "yfov " + check_value_text(yfov) + " rad is not in (0, pi)");
    camera.position = glm::vec3(world[3]);
    const glm::vec3 forward = -glm::vec3(world[2]);
    const glm::vec3 world_up = glm::vec3(world[1]);
    const float forward_length = glm::length(forward);
    if (!(forward_length > 0.0f) || !std::isfinite(forward_length) ||
        !std::isfinite(camera.position.x) || !std::isfinite(camera.position.y) ||
        !std::isfinite(camera.position.z))
        throw loader.error(where, "the camera's world matrix is degenerate or not finite");
    camera.forward = forward / forward_length;
    const glm::vec3 right = glm::cross(camera.forward, world_up);
    const float right_length = glm::length(right);
    if (!(right_length > 1e-6f) || !std::isfinite(right_length))
        throw loader.error(where, "the camera's up (+Y) is parallel to its view direction (-Z)");
    camera.right = right / right_length;
    camera.up = glm::cross(camera.right, camera.forward);
    loader.contents.camera = camera;
}

void add_light(Loader& loader, const tinygltf::Value& extension, const glm::mat4& world,
               const std::string& where) {
    const tinygltf::Model& model = loader.model;
    const int index = extension_index(loader, extension, "light", model.lights.size(), where);
    const tinygltf::Light& source = model.lights[static_cast<std::size_t>(index)];
    const std::string light_where = "KHR_lights_punctual.lights[" + std::to_string(index) + "]";
    if (source.type != "point") {
        loader.note(source.type + " light (skipped; only point lights are read)", where);
        return;
    }
    glm::vec3 colour(1.0f);
    if (!source.color.empty()) {
        if (source.color.size() != 3) throw loader.error(light_where, "color needs 3 numbers");
        for (int c = 0; c < 3; ++c)
            colour[c] =
                json_float(loader, source.color[static_cast<std::size_t>(c)], light_where, "color");
    }
    const float intensity = json_float(loader, source.intensity, light_where, "intensity");
    if (!(intensity >= 0.0f) || colour.x < 0.0f || colour.y < 0.0f || colour.z < 0.0f)
        throw loader.error(light_where, "color and intensity must be >= 0");
    if (source.range > 0.0) loader.note("light range (ignored: no cut-off)", light_where);
    Light light;
    light.type = Light::Type::point;
    light.position = glm::vec3(world[3]);
    light.intensity = colour * intensity;
    if (!std::isfinite(light.position.x) || !std::isfinite(light.position.y) ||
        !std::isfinite(light.position.z) || !std::isfinite(light.intensity.x) ||
        !std::isfinite(light.intensity.y) || !std::isfinite(light.intensity.z))
        throw loader.error(where, "the point light's position or intensity is not finite");
    loader.scene.lights.push_back(light);
    ++loader.contents.point_lights;
}

// Checks that the nodes form a forest (each child index valid, at most one parent, no cycle)
// and returns the default scene's root nodes: scene `scene` (0 when absent), or every node that
// is no other node's child when the file has no scenes.
std::vector<int> root_nodes(Loader& loader) {
    const tinygltf::Model& model = loader.model;
    const std::size_t count = model.nodes.size();
    std::vector<int> parent(count, -1);
    for (std::size_t n = 0; n < count; ++n)
        for (int child : model.nodes[n].children) {
            if (child < 0 || static_cast<std::size_t>(child) >= count)
                throw loader.error(at_index("nodes", n), "child " + std::to_string(child) +
                                                             " does not exist (the file has " +
                                                             std::to_string(count) + " nodes)");
            int& p = parent[static_cast<std::size_t>(child)];
            if (p >= 0)
                throw loader.error(at_index("nodes", static_cast<std::size_t>(child)),
                                   "is a child of two nodes (" + std::to_string(p) + " and " +
                                       std::to_string(n) + "; the nodes must form a tree)");
            p = static_cast<int>(n);
        }
    // Every node reachable from a parentless node; the others lie on a cycle.
    std::vector<bool> reached(count, false);
    std::vector<std::size_t> stack;
    for (std::size_t n = 0; n < count; ++n)
        if (parent[n] < 0) stack.push_back(n);
    while (!stack.empty()) {
        const std::size_t n = stack.back();
        stack.pop_back();
        reached[n] = true;
        for (int child : model.nodes[n].children) stack.push_back(static_cast<std::size_t>(child));
    }
    for (std::size_t n = 0; n < count; ++n)
        if (!reached[n])
            throw loader.error(at_index("nodes", n),
                               "is part of a cycle (the nodes must form a tree)");
    if (model.scenes.empty()) {
        std::vector<int> roots;
        for (std::size_t n = 0; n < count; ++n)
            if (parent[n] < 0) roots.push_back(static_cast<int>(n));
        return roots;
    }
    const int scene = model.defaultScene < 0 ? 0 : model.defaultScene;
    check_exists(loader, scene, model.scenes.size(), "scene", "");
    if (model.scenes.size() > 1)
        loader.note("scenes other than the default (not loaded)",
                    "scene " + std::to_string(scene) + " loaded");
    return model.scenes[static_cast<std::size_t>(scene)].nodes;
}

void add_mesh(Loader& loader, int mesh_index, const glm::mat4& world, const std::string& where) {
    const tinygltf::Model& model = loader.model;
    check_exists(loader, mesh_index, model.meshes.size(), "mesh", where);
    const TransformCheck check = object_to_world(world);
    if (!check.finite) throw loader.error(where, "the world transform is not finite");
    const tinygltf::Mesh& mesh = model.meshes[static_cast<std::size_t>(mesh_index)];
    if (check.singular) {
        loader.scene.load_stats.warnings.push_back(
            loader.path + ": " + where + ": mesh " + std::to_string(mesh_index) +
            " skipped: its world transform is singular (a zero scale)");
        return;
    }
    const ObjectToWorld& to_world = check.to_world;
    if (!mesh.weights.empty()) loader.note("morph target weights (base mesh used)", where);
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p)
        add_primitive(loader, mesh.primitives[p],
                      at_index("meshes", static_cast<std::size_t>(mesh_index)) + "." +
                          at_index("primitives", p),
                      to_world);
}

// Depth-first, children in the order listed, each node's world matrix = its parent's world
// matrix * its local matrix (the roots' parent: `transform`).
void walk_nodes(Loader& loader, const glm::mat4& transform) {
    const tinygltf::Model& model = loader.model;
    std::vector<bool> visited(model.nodes.size(), false);
    const std::vector<int> roots = root_nodes(loader);
    std::vector<std::pair<int, glm::mat4>> stack;
    for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.emplace_back(*it, transform);
    while (!stack.empty()) {
        const auto [index, parent] = stack.back();
        stack.pop_back();
        check_exists(loader, index, model.nodes.size(), "node", "");
        const std::string where = at_index("nodes", static_cast<std::size_t>(index));
        if (visited[static_cast<std::size_t>(index)])
            throw loader.error(where, "is reached twice (the nodes must form a tree)");
        visited[static_cast<std::size_t>(index)] = true;
        const tinygltf::Node& node = model.nodes[static_cast<std::size_t>(index)];
        const glm::mat4 world = parent * local_matrix(loader, node, where);
        if (node.skin >= 0)
            loader.note("skin (mesh drawn unskinned, with its node transform)", where);
        if (!node.weights.empty()) loader.note("morph target weights (base mesh used)", where);
        if (node.mesh >= 0) add_mesh(loader, node.mesh, world, where);
        if (node.camera >= 0) add_camera(loader, node, world, where);
        for (const auto& [name, value] : node.extensions) {
            if (name == "KHR_lights_punctual")
                add_light(loader, value, world, where);
            else
                loader.note("node extension " + name + " (ignored)", where);
        }
        for (auto it = node.children.rbegin(); it != node.children.rend(); ++it)
            stack.emplace_back(*it, world);
    }
}

// ---- Reading the file -------------------------------------------------------------------------

void parse_file(Loader& loader, const std::string& bytes) {
    std::error_code ec;
    FsContext fs_context;
    fs_context.directory =
        std::filesystem::absolute(std::filesystem::path(loader.path), ec).parent_path().string();
    while (fs_context.directory.size() > 1 && fs_context.directory.back() == '/')
        fs_context.directory.pop_back();
    tinygltf::TinyGLTF gltf;
    gltf.SetImageLoader(keep_image_bytes, &loader.data_uri_images);
    tinygltf::FsCallbacks callbacks{};
    callbacks.FileExists = fs_file_exists;
    callbacks.ExpandFilePath = fs_expand_path;
    callbacks.ReadWholeFile = fs_read_file;
    callbacks.WriteWholeFile = fs_write_file;
    callbacks.user_data = &fs_context;
    gltf.SetFsCallbacks(callbacks);

    std::string err, warn;
    bool ok = false;
    const bool binary = bytes.size() >= 4 && bytes.compare(0, 4, "glTF") == 0;
    if (!binary && lower_extension(loader.path) == ".glb")
        throw loader.error("", "not a binary glTF file (no 'glTF' magic at its start)");
    try {
        if (binary) {
            const std::size_t length = check_glb(loader.path, bytes);
            check_json_nesting(std::string_view(bytes).substr(20, load_u32_le(bytes, 12)),
                               loader.path, max_json_depth);
            ok = gltf.LoadBinaryFromMemory(&loader.model, &err, &warn,
                                           reinterpret_cast<const unsigned char*>(bytes.data()),
                                           static_cast<unsigned int>(length), fs_context.directory);
        } else {
            if (bytes.size() > 0xFFFFFFFFu)
                throw loader.error("", "too large for tinygltf (4 GiB at most)");
            check_json_nesting(bytes, loader.path, max_json_depth);
            ok = gltf.LoadASCIIFromString(&loader.model, &err, &warn, bytes.data(),
                                          static_cast<unsigned int>(bytes.size()),
                                          fs_context.directory);
        }
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        throw loader.error("", std::string("tinygltf failed: ") + e.what());
    }
    if (!ok)
        throw loader.error("", "tinygltf: " + (err.empty() ? std::string("cannot parse the file")
                                                           : one_line(err)));
    if (!warn.empty())
        loader.scene.load_stats.warnings.push_back(loader.path + ": tinygltf: " + one_line(warn));
}

const std::set<std::string>& handled_extensions() {
    static const std::set<std::string> names = {"KHR_lights_punctual",
                                                "KHR_materials_emissive_strength"};
    return names;
}

}  // namespace

GltfContents load_gltf_into(Scene& scene, const std::string& gltf_path, const glm::mat4& transform,
                            TextureCache& cache, const std::string& referenced_at) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(gltf_path, ec))
        throw Error((referenced_at.empty() ? gltf_path : referenced_at) + ": glTF file '" +
                    gltf_path + "' not found");
    const std::string bytes = read_file(gltf_path);

    Loader loader(scene, gltf_path, cache);
    loader.directory = std::filesystem::path(gltf_path).parent_path().string();
    loader.file_name = std::filesystem::path(gltf_path).filename().string();
    loader.canonical = std::filesystem::weakly_canonical(gltf_path, ec).string();
    parse_file(loader, bytes);
    const tinygltf::Model& model = loader.model;

    for (const std::string& name : model.extensionsRequired)
        if (handled_extensions().count(name) == 0)
            throw loader.error(
                "", "extensionsRequired names " + name + ", which fovref does not implement");
    for (const std::string& name : model.extensionsUsed)
        if (handled_extensions().count(name) == 0)
            loader.note("extension " + name + " (ignored)", "extensionsUsed");
    if (!model.skins.empty()) loader.note("skins (meshes drawn unskinned)", "skins");
    if (!model.animations.empty())
        loader.note("animations (the nodes' static transforms used)", "animations");

    convert_materials(loader);
    walk_nodes(loader, transform);

    SceneLoadStats& stats = scene.load_stats;
    note_dropped_total(scene, gltf_path, loader.dropped_here);
    static const char* mode_names[4] = {"POINTS", "LINES", "LINE_LOOP", "LINE_STRIP"};
    for (const auto& [mode, count] : loader.ignored_modes) {
        // Counted like OBJ's p and l statements (scene info's "ignored" line).
        (mode == TINYGLTF_MODE_POINTS ? stats.points_ignored : stats.lines_ignored) += count;
        stats.warnings.push_back(gltf_path + ": " + std::to_string(count) +
                                 " primitive(s) of mode " + std::to_string(mode) + " (" +
                                 mode_names[mode] + ") ignored (only triangles are loaded)");
    }

    // Unsupported features: one line each, with up to max_listed_places places.
    for (const auto& [feature, places] : loader.unsupported) {
        std::string line = gltf_path + ": " + feature + ": ";
        std::set<std::string> seen;
        std::size_t listed = 0, distinct = 0;
        for (const std::string& place : places) {
            if (!seen.insert(place).second) continue;
            ++distinct;
            if (listed < max_listed_places) {
                line += (listed == 0 ? "" : ", ") + place;
                ++listed;
            }
        }
        if (distinct > listed) line += " and " + std::to_string(distinct - listed) + " more";
        loader.contents.unsupported.push_back(line);
    }
    std::sort(loader.contents.unsupported.begin(), loader.contents.unsupported.end());
    return std::move(loader.contents);
}

}  // namespace fovref
