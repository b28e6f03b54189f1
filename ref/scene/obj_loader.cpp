// OBJ + MTL meshes (SPEC §2): texture names by tinyobjloader, every number, face, material name
// and usemtl by our own pre-scan, checked against tinyobjloader's reading.
//
// tinyobjloader reports few problems and almost never with a line: it reads a malformed number
// as 0, "nan" as 0, and an out-of-range face index as an error without context. So before
// handing the text to it, a validating pre-scan walks the OBJ (and every MTL it names)
// statement by statement: numbers must parse completely and be finite binary32, face indices
// must be in range (1-based or negative-relative, as OBJ defines them). Each failure is thrown as
// fovref::Error "file:line: message". The pre-scan also records the line of every face (which
// is how a zero-area triangle's warning names its line) and the material each face uses.
//
// Quirks of real-world files (docs/obj-quirks.md): an undefined material, a missing MTL file or
// texture, material names with blanks, backslashes in paths, and a few more are accepted with a
// warning in load_stats.warnings; with `strict` (--strict-obj) they are errors as before. A
// UTF-16 file or one with NUL bytes is always an error.
//
// Numbers: the pre-scan parses each one with std::from_chars<float>, i.e. correctly rounded
// straight to binary32, and keeps the v, vt, vn and MTL Kd/Ks/Ke/Ns/Pr values. These are the
// values used. tinyobjloader's own values are not: its tryParseDouble builds the number with
// libm std::pow and rounds twice (decimal -> binary64 -> binary32), so a decimal close to a
// binary32 rounding boundary ("1.00000005960464477539062500001") can come out one ulp away from
// the correctly rounded float that any other careful reader (a GPU tool) gets, and libm is not
// allowed to feed a golden (SPEC §0). tinyobjloader's vertex/normal/texcoord indices count
// v/vt/vn statements in file order, exactly as the pre-scan stores them (checked by comparing
// the counts), so they index the pre-scan's arrays directly.
//
// Materials: the pre-scan reads the MTL files; tinyobjloader's ParseTextureNameAndOption splits a
// map_Kd statement into its options and the file name. The OBJ text tinyobjloader parses has its
// mtllib and usemtl statements commented out: which material a face uses is the pre-scan's
// (usemtl names may contain blanks, which tinyobjloader cuts at the first blank).
//
// Faces: the pre-scan's (every corner already checked and resolved), which tinyobjloader's must
// equal corner for corner (tinyobjloader keeps a face's corner count in an unsigned char, so the
// pre-scan's faces are the ones used: faces of more than 255 corners exist in real files).
// triangulate_polygon splits each (a fan for convex polygons, ear clipping for concave ones), so
// the triangle order is the face order of the file. Each triangle is transformed to world space,
// dropped if its area is zero or not finite (counted), and given geometric normals where the file
// has none (counted) and uv (0,0) where it has no texture coordinates.
#include <tiny_obj_loader.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>
#include <string_view>
#include <vector>

#include "ref/core/error.h"
#include "ref/image/image_io.h"
#include "ref/scene/mesh_builder.h"
#include "ref/scene/obj_loader.h"
#include "ref/scene/polygon.h"
#include "ref/scene/scene_file.h"

namespace fovref {

namespace {

std::string location(const std::string& file, int line) {
    return file + ":" + std::to_string(line);
}

std::string directory_of(const std::string& path) {
    return std::filesystem::path(path).parent_path().string();
}

std::string join_path(const std::string& directory, const std::string& name) {
    if (directory.empty()) return name;
    return (std::filesystem::path(directory) / name).string();
}

// tinyobjloader's error text reworded as "line N: message" when it names a line ("Failed parse
// `l' line(e.g. zero value for vertex index. line 4.)"), trailing newlines dropped.
std::string tinyobj_message(std::string text) {
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
    const std::size_t at = text.rfind("line ");
    if (at != std::string::npos) {
        std::size_t end = at + 5;
        while (end < text.size() && text[end] >= '0' && text[end] <= '9') ++end;
        if (end > at + 5) return text.substr(at + 5, end - at - 5) + ": tinyobjloader: " + text;
    }
    return "tinyobjloader: " + text;
}

// --- Statements: non-empty, non-comment lines split on blanks -----------------------------------

// Calls fn(line, tokens) for each statement. Lines end at "\n", "\r\n" or a lone "\r" (as
// tinyobjloader's reader does), so line numbers agree with it.
template <class Fn>
void for_each_statement(const std::string& text, Fn&& fn) {
    std::vector<std::string_view> tokens;
    std::size_t pos = 0;
    int line = 0;
    while (pos < text.size()) {
        std::size_t end = pos;
        while (end < text.size() && text[end] != '\n' && text[end] != '\r') ++end;
        ++line;
        tokens.clear();
        std::size_t i = pos;
        while (i < end) {
            while (i < end && (text[i] == ' ' || text[i] == '\t')) ++i;
            std::size_t start = i;
            while (i < end && text[i] != ' ' && text[i] != '\t') ++i;
            if (i > start) tokens.emplace_back(text.data() + start, i - start);
        }
        if (!tokens.empty() && tokens[0][0] != '#') fn(line, tokens);
        pos = end;
        if (pos < text.size() && text[pos] == '\r') {
            ++pos;
            if (pos < text.size() && text[pos] == '\n') ++pos;
        } else if (pos < text.size()) {
            ++pos;  // '\n'
        }
    }
}

// --- Quirks -------------------------------------------------------------------------------------

// Where a file's quirks go: with `strict`, a quirk is the error it always was; otherwise it is a
// warning ("file:line: message") and loading goes on.
struct QuirkLog {
    bool strict = false;
    std::vector<std::string>* warnings = nullptr;
    int* malformed_numbers = nullptr;  ///< numbers read from their valid start (first few listed)

    void quirk(const std::string& file, int line, const std::string& strict_message,
               const std::string& warning) const {
        if (strict) throw file_error(file, line, strict_message);
        warnings->push_back(file_error(file, line, warning).what());
    }
};

// --- Numbers ------------------------------------------------------------------------------------

// Parses a whole token as a finite binary32 number (correctly rounded, std::from_chars), or
// throws "file:line: ..." saying what is wrong with it.
// With quirks (`log` not strict), a token that starts with a number and goes on with other
// characters ("3.1+e2") is read as that number, with a warning, as C's strtod and most OBJ readers
// read it.
float parse_number(std::string_view token, const std::string& file, int line, const char* what,
                   const QuirkLog* log) {
    std::string_view digits = token;
    if (digits.size() > 1 && digits[0] == '+') digits.remove_prefix(1);
    float value = 0.0f;
    auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
    if (ec == std::errc::result_out_of_range)
        throw file_error(file, line,
                         std::string(what) + ": number '" + std::string(token) +
                             "' is outside the binary32 range");
    const bool prefix_only = ec == std::errc() && end != digits.data() + digits.size();
    if (prefix_only && log != nullptr && !log->strict && std::isfinite(value)) {
        const std::string read(digits.data(), static_cast<std::size_t>(end - digits.data()));
        if (++*log->malformed_numbers <= max_listed_warnings)
            log->warnings->push_back(location(file, line) + ": " + what + ": malformed number '" +
                                     std::string(token) + "' read as " + read +
                                     " (its valid start)");
        return value;
    }
    if (ec != std::errc() || prefix_only)
        throw file_error(file, line,
                         std::string(what) + ": malformed number '" + std::string(token) + "'");
    if (!std::isfinite(value))
        throw file_error(
            file, line,
            std::string(what) + ": number '" + std::string(token) + "' is NaN or infinite");
    return value;
}

// Parses a statement's numbers (between min_count and max_count of them, at most 7) into
// values[0 .. count) and returns count; throws "file:line: ..." on a wrong count or bad number.
std::size_t parse_numbers(const std::vector<std::string_view>& tokens, std::size_t min_count,
                          std::size_t max_count, const std::string& file, int line,
                          std::array<float, 7>& values, const QuirkLog& log) {
    const std::size_t count = tokens.size() - 1;
    if (count < min_count || count > max_count) {
        std::string expected = min_count == max_count
                                   ? std::to_string(min_count)
                                   : std::to_string(min_count) + " to " + std::to_string(max_count);
        throw file_error(file, line,
                         "'" + std::string(tokens[0]) + "' needs " + expected + " numbers, got " +
                             std::to_string(count));
    }
    for (std::size_t k = 1; k < tokens.size(); ++k)
        values[k - 1] = parse_number(tokens[k], file, line, std::string(tokens[0]).c_str(), &log);
    return count;
}

// The text of a statement after its keyword, blanks at both ends dropped ("" when none).
std::string_view rest_of_statement(const std::vector<std::string_view>& tokens) {
    if (tokens.size() < 2) return {};
    const char* begin = tokens[1].data();
    const char* end = tokens.back().data() + tokens.back().size();
    return {begin, static_cast<std::size_t>(end - begin)};
}

// A file name as written, with Windows separators turned into '/' (a quirk when there were any).
std::string portable_path(std::string_view name, const QuirkLog& log, const std::string& file,
                          int line, const char* what) {
    std::string path(name);
    if (path.find('\\') == std::string::npos) return path;
    std::string fixed = path;
    for (char& c : fixed)
        if (c == '\\') c = '/';
    log.quirk(file, line, std::string(what) + " '" + path + "' uses '\\' as a path separator",
              std::string(what) + " '" + path + "' uses '\\' as a path separator; read as '" +
                  fixed + "'");
    return fixed;
}

// Bytes a text file must not hold: UTF-16/32 (a byte-order mark, or NUL bytes) is an error that
// says so; a UTF-8 byte-order mark is blanked (three spaces). Lone-CR line breaks and a missing
// final line break are read as they are, with a warning.
std::string checked_text(std::string text, const std::string& path,
                         std::vector<std::string>& warnings) {
    const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
    if (text.size() >= 2 &&
        ((byte(0) == 0xFF && byte(1) == 0xFE) || (byte(0) == 0xFE && byte(1) == 0xFF)))
        throw Error(path + ": the file is UTF-16 text (byte-order mark " +
                    std::string(byte(0) == 0xFF ? "FF FE" : "FE FF") +
                    "); save it as UTF-8 or ASCII");
    const std::size_t nul = text.find('\0');
    if (nul != std::string::npos) {
        // Lines counted as for_each_statement counts them: "\n", "\r\n" or a lone "\r".
        int line = 1;
        for (std::size_t i = 0; i < nul; ++i)
            line += text[i] == '\r' || (text[i] == '\n' && (i == 0 || text[i - 1] != '\r')) ? 1 : 0;
        throw file_error(path, line,
                         "NUL byte at offset " + std::to_string(nul) +
                             ": the file is binary, or UTF-16/UTF-32 text (save it as UTF-8 or "
                             "ASCII)");
    }
    if (text.size() >= 3 && byte(0) == 0xEF && byte(1) == 0xBB && byte(2) == 0xBF)
        text.replace(0, 3, "   ");
    bool lone_cr = false;
    for (std::size_t i = 0; i < text.size() && !lone_cr; ++i)
        lone_cr = text[i] == '\r' && (i + 1 == text.size() || text[i + 1] != '\n');
    if (lone_cr)
        warnings.push_back(path + ": lines end in a lone CR (classic Mac OS); read as line breaks");
    if (!text.empty() && text.back() != '\n' && text.back() != '\r')
        warnings.push_back(path +
                           ": the last line has no line break (is the file cut short?); read as "
                           "written");
    return text;
}

// --- MTL pre-scan ----------------------------------------------------------------------------

// What the pre-scan learns about one material: where it is defined and its numbers, correctly
// rounded (see the top of the file). Absent values keep tinyobjloader's defaults (Kd, Ks, Ke 0,
// Ns 1, Pr 0); a repeated statement overrides the earlier one, as in tinyobjloader.
struct MtlMaterialInfo {
    std::string name;
    std::string file;  ///< the MTL file that defines it
    int line = 0;      ///< its newmtl line
    glm::vec3 kd{0.0f};
    glm::vec3 ks{0.0f};
    glm::vec3 ke{0.0f};
    float ns = 1.0f;
    float pr = 0.0f;
    bool has_kd = false;
    bool has_pr = false;
    bool has_ns = false;
    std::string map_kd;  ///< map_Kd's file name as written ("" = none)
    int map_kd_line = 0;
    bool duplicate = false;  ///< a second newmtl of an earlier name (ignored, with a warning)
};

struct MtlScan {
    std::vector<MtlMaterialInfo> materials;  ///< every newmtl, in mtllib then file order
    std::map<std::string, int> by_name;      ///< name -> first definition in `materials`
    std::set<std::string> paths;             ///< MTL files read (each is read once)
    MtlMaterialInfo ignored;                 ///< where a nameless newmtl's statements go
};

// newmtl NAME: a new material (or, without a name, a sink for its statements); returns the
// material the following statements describe.
MtlMaterialInfo* mtl_newmtl(const std::string& mtl_path, int line,
                            const std::vector<std::string_view>& tokens, MtlScan& scan,
                            const QuirkLog& log) {
    if (tokens.size() < 2) {
        // tinyobjloader keeps no material without a name either, so the two agree.
        log.quirk(mtl_path, line, "newmtl needs a material name",
                  "newmtl without a name: its statements up to the next newmtl are ignored");
        return &scan.ignored;
    }
    const std::string name(rest_of_statement(tokens));
    if (tokens.size() > 2)
        log.quirk(mtl_path, line, "newmtl needs one material name without blanks",
                  "material name '" + name + "' contains blanks (accepted as written)");
    MtlMaterialInfo info;
    info.name = name;
    info.file = mtl_path;
    info.line = line;
    auto [it, inserted] = scan.by_name.emplace(name, static_cast<int>(scan.materials.size()));
    if (!inserted) {
        const MtlMaterialInfo& first = scan.materials[static_cast<std::size_t>(it->second)];
        log.quirk(
            mtl_path, line,
            "material '" + name + "' is already defined at " + location(first.file, first.line),
            "material '" + name + "' is defined again (first at " +
                location(first.file, first.line) + "); this definition is ignored");
        info.duplicate = true;
    }
    scan.materials.push_back(info);
    return &scan.materials.back();
}

// map_Kd [options] FILE: options (-s 1 1 1, -bm 0.5, ...) then the file name, which may contain
// blanks: tinyobjloader's reading of the statement.
void mtl_map_kd(const std::string& mtl_path, int line, const std::vector<std::string_view>& tokens,
                MtlMaterialInfo& current) {
    if (tokens.size() < 2) throw file_error(mtl_path, line, "map_Kd needs a file name");
    const std::string rest(rest_of_statement(tokens));
    tinyobj::texture_option_t options;
    std::string name;
    if (!tinyobj::ParseTextureNameAndOption(&name, &options, rest.c_str()) || name.empty())
        throw file_error(mtl_path, line, "map_Kd needs a file name");
    while (!name.empty() && (name.back() == ' ' || name.back() == '\t')) name.pop_back();
    current.map_kd = name;
    current.map_kd_line = line;
}

// Ns EXPONENT or Pr ROUGHNESS: one number in its range.
void mtl_scalar(const std::string& mtl_path, int line, const std::vector<std::string_view>& tokens,
                MtlMaterialInfo& current, const QuirkLog& log) {
    const std::string_view keyword = tokens[0];
    std::array<float, 7> values{};
    parse_numbers(tokens, 1, 1, mtl_path, line, values, log);
    const float value = values[0];
    if (keyword == "Pr" && !(value >= 0.0f && value <= 1.0f))
        throw file_error(mtl_path, line, "Pr (roughness) must be in [0, 1]");
    if (keyword == "Ns" && !(value >= 0.0f)) throw file_error(mtl_path, line, "Ns must be >= 0");
    if (keyword == "Pr") {
        current.pr = value;
        current.has_pr = true;
    } else {
        current.ns = value;
        current.has_ns = true;
    }
}

// Kd, Ks or Ke: r g b, or one value for all three (as the MTL format defines it), each >= 0.
void mtl_colour(const std::string& mtl_path, int line, const std::vector<std::string_view>& tokens,
                MtlMaterialInfo& current, const QuirkLog& log) {
    const std::string_view keyword = tokens[0];
    std::array<float, 7> values{};
    const std::size_t count = parse_numbers(tokens, 1, 3, mtl_path, line, values, log);
    if (count == 2)
        throw file_error(mtl_path, line,
                         "'" + std::string(keyword) + "' needs 1 or 3 numbers, got 2");
    const glm::vec3 colour =
        count == 1 ? glm::vec3(values[0]) : glm::vec3(values[0], values[1], values[2]);
    if (colour.x < 0.0f || colour.y < 0.0f || colour.z < 0.0f)
        throw file_error(mtl_path, line, std::string(keyword) + " values must be >= 0");
    if (keyword == "Kd") {
        current.kd = colour;
        current.has_kd = true;
    } else if (keyword == "Ks") {
        current.ks = colour;
    } else {
        current.ke = colour;
    }
}

void scan_mtl(const std::string& mtl_path, const std::string& text, MtlScan& scan,
              const QuirkLog& log) {
    MtlMaterialInfo* current = nullptr;
    for_each_statement(text, [&](int line, const std::vector<std::string_view>& tokens) {
        const std::string_view keyword = tokens[0];
        if (keyword == "newmtl") {
            current = mtl_newmtl(mtl_path, line, tokens, scan, log);
            return;
        }
        const bool used = keyword == "Kd" || keyword == "Ks" || keyword == "Ke" ||
                          keyword == "Ns" || keyword == "Pr" || keyword == "map_Kd";
        if (!used) return;  // other MTL statements (Ka, d, illum, Ni, map_Bump, ...) are ignored
        if (current == nullptr)
            throw file_error(mtl_path, line, "'" + std::string(keyword) + "' before any newmtl");
        if (keyword == "map_Kd")
            mtl_map_kd(mtl_path, line, tokens, *current);
        else if (keyword == "Ns" || keyword == "Pr")
            mtl_scalar(mtl_path, line, tokens, *current, log);
        else
            mtl_colour(mtl_path, line, tokens, *current, log);
    });
}

// --- OBJ pre-scan ----------------------------------------------------------------------------

// The OBJ's numbers, correctly rounded, in statement order: element i of positions is the i-th
// "v" statement (its x y z; w or a vertex colour are checked and dropped), of normals the i-th
// "vn", of texcoords the i-th "vt" (u and v; v = 0 when absent, w dropped, as tinyobjloader).
/// One face corner: 0-based indices into ObjScan's positions, texcoords, normals (-1: none).
struct ObjCorner {
    int vertex = -1, texcoord = -1, normal = -1;
};

struct ObjScan {
    std::vector<ObjCorner> corners;        ///< every face's corners, face after face
    std::vector<std::size_t> face_starts;  ///< index of each face's first corner in `corners`
    std::vector<int> face_lines;           ///< line of each f statement, in file order
    std::vector<int> face_materials;       ///< index into mtl.materials of each face; -1 = default
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;
    std::vector<glm::vec2> texcoords;
    std::int64_t points = 0;  ///< vertex indices of "p" statements
    std::int64_t lines = 0;   ///< "l" statements
    MtlScan mtl;
};

// One face corner "v", "v/t", "v//n" or "v/t/n"; checks each index against the count of
// elements defined so far (negative indices count back from the last one, OBJ's relative form)
// and returns them 0-based.
ObjCorner check_corner(std::string_view corner, const ObjScan& scan, const std::string& file,
                       int line) {
    std::string_view parts[3];
    int part_count = 0;
    std::size_t start = 0;
    while (true) {
        std::size_t slash = corner.find('/', start);
        if (part_count == 3)
            throw file_error(file, line, "malformed face corner '" + std::string(corner) + "'");
        parts[part_count++] = corner.substr(
            start, slash == std::string_view::npos ? std::string_view::npos : slash - start);
        if (slash == std::string_view::npos) break;
        start = slash + 1;
    }
    const char* kinds[3] = {"vertex", "texture coordinate", "normal"};
    const std::size_t counts[3] = {scan.positions.size(), scan.texcoords.size(),
                                   scan.normals.size()};
    int resolved_index[3] = {-1, -1, -1};
    for (int k = 0; k < part_count; ++k) {
        if (parts[k].empty()) {
            if (k == 1 && part_count == 3) continue;  // v//n
            throw file_error(file, line, "malformed face corner '" + std::string(corner) + "'");
        }
        long long index = 0;
        auto [end, ec] = std::from_chars(parts[k].data(), parts[k].data() + parts[k].size(), index);
        if (ec != std::errc() || end != parts[k].data() + parts[k].size())
            throw file_error(
                file, line,
                "malformed " + std::string(kinds[k]) + " index '" + std::string(parts[k]) + "'");
        const long long count = static_cast<long long>(counts[k]);
        const long long resolved = index < 0 ? count + index + 1 : index;
        if (index == 0 || resolved < 1 || resolved > count)
            throw file_error(file, line,
                             std::string(kinds[k]) + " index " + std::to_string(index) +
                                 " out of range (" + std::to_string(count) + " defined so far)");
        resolved_index[k] = static_cast<int>(resolved - 1);
    }
    return {resolved_index[0], resolved_index[1], resolved_index[2]};
}

// Reads the MTL file `name` (as an mtllib statement of obj_path's line wrote it) into scan.mtl;
// returns false when there is no such file.
bool read_mtllib(const std::string& obj_path, int line, const std::string& name, ObjScan& scan,
                 const QuirkLog& log) {
    const std::string mtl_path = join_path(directory_of(obj_path), name);
    std::error_code ec;
    if (!std::filesystem::is_regular_file(mtl_path, ec)) return false;
    if (!scan.mtl.paths.insert(mtl_path).second) return true;  // each file is read once
    std::string mtl_text;
    try {
        mtl_text = read_file(mtl_path);
    } catch (const Error& e) {
        throw file_error(obj_path, line, e.what());
    }
    mtl_text = checked_text(std::move(mtl_text), mtl_path, *log.warnings);
    scan_mtl(mtl_path, mtl_text, scan.mtl, log);
    return true;
}

// mtllib: one file name; with quirks, a name with blanks, or else several names.
void scan_mtllib(const std::string& obj_path, int line, const std::vector<std::string_view>& tokens,
                 ObjScan& scan, const QuirkLog& log) {
    if (tokens.size() < 2) throw file_error(obj_path, line, "mtllib needs a file name");
    if (tokens.size() > 2 && log.strict)
        throw file_error(obj_path, line,
                         "mtllib needs exactly one file name (use one mtllib per file)");
    const std::string whole =
        portable_path(rest_of_statement(tokens), log, obj_path, line, "MTL file");
    if (read_mtllib(obj_path, line, whole, scan, log)) {
        if (tokens.size() > 2)
            log.warnings->push_back(location(obj_path, line) + ": MTL file name '" + whole +
                                    "' contains blanks (accepted as written)");
        return;
    }
    std::vector<std::string> names{whole};
    if (tokens.size() > 2) {  // several files, as tinyobjloader reads mtllib
        log.warnings->push_back(location(obj_path, line) + ": mtllib names " +
                                std::to_string(tokens.size() - 1) + " files (no file is named '" +
                                whole + "'); each is read");
        names.clear();
        for (std::size_t k = 1; k < tokens.size(); ++k)
            names.push_back(portable_path(tokens[k],
                                          QuirkLog{false, log.warnings, log.malformed_numbers},
                                          obj_path, line, "MTL file"));
    }
    for (const std::string& name : names) {
        if (read_mtllib(obj_path, line, name, scan, log)) continue;
        const std::string looked = join_path(directory_of(obj_path), name);
        log.quirk(obj_path, line, "MTL file '" + name + "' not found (looked for " + looked + ")",
                  "MTL file '" + name + "' not found (looked for " + looked +
                      "); faces that use its materials get the default material");
    }
}

// The material of the faces after a usemtl: resolved when the scan ends (see scan_obj).
struct PendingUsemtl {
    std::string name;
    int line = 0;
    bool defined_before = false;
    bool no_name = false;  ///< "usemtl" alone: the default material, already warned about
};

// f V1 V2 V3 ...: the face's corners, checked, with the usemtl in force.
void obj_face(const std::string& obj_path, int line, const std::vector<std::string_view>& tokens,
              ObjScan& scan, std::vector<int>& face_usemtl, int usemtl) {
    const std::size_t corners = tokens.size() - 1;
    if (corners < 3)
        throw file_error(obj_path, line,
                         "a face needs at least 3 vertices, got " + std::to_string(corners));
    scan.face_starts.push_back(scan.corners.size());
    for (std::size_t k = 1; k < tokens.size(); ++k)
        scan.corners.push_back(check_corner(tokens[k], scan, obj_path, line));
    scan.face_lines.push_back(line);
    face_usemtl.push_back(usemtl);
}

// usemtl NAME: the material of the faces that follow (without a name: the default material).
void obj_usemtl(const std::string& obj_path, int line, const std::vector<std::string_view>& tokens,
                const ObjScan& scan, std::vector<PendingUsemtl>& usemtls, const QuirkLog& log) {
    if (tokens.size() != 2 && log.strict)
        throw file_error(obj_path, line, "usemtl needs one material name without blanks");
    if (tokens.size() < 2) {  // the default material from here on
        log.warnings->push_back(location(obj_path, line) +
                                ": usemtl without a material name: the default material");
        usemtls.push_back({"", line, false, true});
        return;
    }
    const std::string name(rest_of_statement(tokens));
    const bool defined = scan.mtl.by_name.count(name) != 0;
    if (!defined && log.strict)
        throw file_error(obj_path, line,
                         "material '" + name + "' is not defined by an mtllib before this line");
    usemtls.push_back({name, line, defined});
}

// l or p: lines and points carry no triangles, but tinyobjloader stops on a bad index in them
// with a message of its own: check them here, with file and line.
void obj_lines_points(const std::string& obj_path, int line,
                      const std::vector<std::string_view>& tokens, ObjScan& scan) {
    const bool is_line = tokens[0] == "l";
    if (tokens.size() < (is_line ? 3u : 2u))
        throw file_error(obj_path, line,
                         std::string(is_line ? "a line needs 2" : "a point needs 1") +
                             " or more vertex indices");
    for (std::size_t k = 1; k < tokens.size(); ++k) check_corner(tokens[k], scan, obj_path, line);
    if (is_line)
        ++scan.lines;
    else
        scan.points += static_cast<std::int64_t>(tokens.size() - 1);
}

// Materials of the faces: a usemtl names a material of any MTL file the OBJ reads (strict: of
// one read before its line); an undefined one gives its faces the default material, with one
// warning per name.
void resolve_face_materials(const std::string& obj_path, const std::vector<PendingUsemtl>& usemtls,
                            const std::vector<int>& face_usemtl, ObjScan& scan,
                            const QuirkLog& log) {
    std::vector<int> usemtl_material(usemtls.size(), -1);
    std::set<std::string> reported;
    for (std::size_t u = 0; u < usemtls.size(); ++u) {
        if (usemtls[u].no_name) continue;
        auto it = scan.mtl.by_name.find(usemtls[u].name);
        if (it != scan.mtl.by_name.end()) {
            usemtl_material[u] = it->second;
        } else if (reported.insert(usemtls[u].name).second) {
            log.warnings->push_back(location(obj_path, usemtls[u].line) + ": material '" +
                                    usemtls[u].name +
                                    "' is not defined by any MTL file; its faces get the default "
                                    "material");
        }
    }
    for (int u : face_usemtl) scan.face_materials.push_back(u < 0 ? -1 : usemtl_material[u]);
}

ObjScan scan_obj(const std::string& obj_path, const std::string& text, const QuirkLog& log) {
    ObjScan scan;
    std::vector<PendingUsemtl> usemtls;  // every usemtl, in file order
    std::vector<int> face_usemtl;        // per face: index into usemtls, -1 = none yet
    for_each_statement(text, [&](int line, const std::vector<std::string_view>& tokens) {
        const std::string_view keyword = tokens[0];
        std::array<float, 7> values{};
        if (keyword == "v") {
            // x y z, optionally w or r g b (vertex colour), as tinyobjloader reads them.
            parse_numbers(tokens, 3, 7, obj_path, line, values, log);
            scan.positions.emplace_back(values[0], values[1], values[2]);
        } else if (keyword == "vn") {
            parse_numbers(tokens, 3, 3, obj_path, line, values, log);
            scan.normals.emplace_back(values[0], values[1], values[2]);
        } else if (keyword == "vt") {
            // u, optionally v (default 0) and w (dropped).
            const std::size_t count = parse_numbers(tokens, 1, 3, obj_path, line, values, log);
            scan.texcoords.emplace_back(values[0], count >= 2 ? values[1] : 0.0f);
        } else if (keyword == "f") {
            obj_face(obj_path, line, tokens, scan, face_usemtl,
                     static_cast<int>(usemtls.size()) - 1);
        } else if (keyword == "mtllib") {
            scan_mtllib(obj_path, line, tokens, scan, log);
        } else if (keyword == "usemtl") {
            obj_usemtl(obj_path, line, tokens, scan, usemtls, log);
        } else if (keyword == "l" || keyword == "p") {
            obj_lines_points(obj_path, line, tokens, scan);
        }
        // Other statements (o, g, s, vp, ...) are left to tinyobjloader, which ignores them for
        // triangle meshes.
    });
    resolve_face_materials(obj_path, usemtls, face_usemtl, scan, log);
    return scan;
}

// The OBJ text tinyobjloader parses: line breaks as "\n" (the pre-scan's lines, so
// tinyobjloader's line numbers agree), its mtllib and usemtl statements commented out (the
// pre-scan resolves materials).
std::string tinyobj_text(const std::string& text) {
    std::string out;
    out.reserve(text.size());
    for (std::size_t i = 0; i < text.size(); ++i) {
        if (text[i] == '\r') {
            out.push_back('\n');
            if (i + 1 < text.size() && text[i + 1] == '\n') ++i;
        } else {
            out.push_back(text[i]);
        }
    }
    std::size_t pos = 0;
    while (pos < out.size()) {
        std::size_t start = pos;
        while (start < out.size() && (out[start] == ' ' || out[start] == '\t')) ++start;
        if (out.compare(start, 6, "usemtl") == 0 || out.compare(start, 6, "mtllib") == 0)
            out[start] = '#';
        pos = out.find('\n', pos);
        if (pos == std::string::npos) break;
        ++pos;
    }
    return out;
}

// --- Materials --------------------------------------------------------------------------------

// The file a texture name refers to, relative to the MTL file's directory: as written; with
// quirks, '\' read as '/' and, where no file has that name, the one file of the directory whose
// name differs only in letter case (a name written on a case-insensitive file system). "" when
// there is none (the caller reports it).
std::string find_texture(const std::string& directory, const std::string& name, const QuirkLog& log,
                         const std::string& mtl_path, int line, TextureCache& cache) {
    std::error_code ec;
    const std::string as_written = join_path(directory, name);
    if (std::filesystem::is_regular_file(as_written, ec)) return as_written;
    const std::string portable = portable_path(name, log, mtl_path, line, "texture path");
    const std::string path = join_path(directory, portable);
    if (std::filesystem::is_regular_file(path, ec)) return path;
    if (log.strict) return "";
    const std::filesystem::path wanted(path);
    const std::filesystem::path folder =
        wanted.has_parent_path() ? wanted.parent_path() : std::filesystem::path(".");
    auto lower = [](std::string text) {
        for (char& c : text)
            if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
        return text;
    };
    const std::string wanted_name = lower(wanted.filename().string());
    // The directory's regular files, listed once per scene load and sorted (directory order is
    // not deterministic).
    auto listed = cache.directory_files.find(folder.string());
    if (listed == cache.directory_files.end()) {
        std::vector<std::string> files;
        for (std::filesystem::directory_iterator it(folder, ec), end; !ec && it != end;
             it.increment(ec))
            if (it->is_regular_file(ec)) files.push_back(it->path().string());
        std::sort(files.begin(), files.end());
        listed = cache.directory_files.emplace(folder.string(), std::move(files)).first;
    }
    std::vector<std::string> matches;
    for (const std::string& file : listed->second)
        if (lower(std::filesystem::path(file).filename().string()) == wanted_name)
            matches.push_back(file);
    if (matches.size() != 1) return "";
    log.warnings->push_back(location(mtl_path, line) + ": texture '" + portable +
                            "' not found; using '" +
                            std::filesystem::path(matches[0]).filename().string() +
                            "', whose name differs only in letter case");
    return matches[0];
}

// A material from the pre-scan's reading of its MTL statements. A texture that cannot be found or
// read is a quirk: the material is drawn without it.
Material convert_material(Scene& scene, const MtlMaterialInfo& info, TextureCache& cache,
                          const QuirkLog& log) {
    Material material;
    material.name = utf8_or_latin1(info.name);
    if (material.name != info.name)
        log.warnings->push_back(location(info.file, info.line) + ": material name '" +
                                material.name + "' is not UTF-8; read as Latin-1");
    const std::string& texture_name = info.map_kd;
    int texture = -1;
    if (!texture_name.empty()) {
        const std::string where = location(info.file, info.map_kd_line);
        const std::string directory = directory_of(info.file);
        const std::string path =
            find_texture(directory, texture_name, log, info.file, info.map_kd_line, cache);
        if (path.empty()) {
            std::string tried = texture_name;  // the '/' form is the one last tried
            std::replace(tried.begin(), tried.end(), '\\', '/');
            const std::string looked = join_path(directory, tried);
            log.quirk(info.file, info.map_kd_line,
                      "texture '" + texture_name + "' not found (looked for " + looked + ")",
                      "texture '" + texture_name + "' not found (looked for " + looked +
                          "); material '" + info.name + "' is drawn without it");
        } else {
            try {
                // Named as written, with '/' for '\\' (the name the exporter derives its file
                // name from).
                std::string name = utf8_or_latin1(texture_name);
                std::replace(name.begin(), name.end(), '\\', '/');
                texture = load_texture_file(scene, path, name, cache, where);
            } catch (const Error& e) {
                if (log.strict) throw;
                log.warnings->push_back(std::string(e.what()) + "; material '" + info.name +
                                        "' is drawn without it");
            }
        }
    }
    // Kd absent: white under a texture (the texture is the albedo), else Material's default 0.8.
    if (info.has_kd) {
        material.albedo = info.kd;
    } else {
        material.albedo = glm::vec3(texture >= 0 ? 1.0f : 0.8f);
    }
    material.texture = texture;
    material.emission = info.ke;
    material.specular = info.ks;
    // Roughness: Pr when given, else from Ns, else 1 (the roughest).
    if (info.has_pr) {
        material.roughness = info.pr;
    } else if (info.has_ns) {
        material.roughness = ns_to_roughness(info.ns);
    }
    return material;
}

// Element `index` (0-based, as tinyobjloader resolved it) of a pre-scanned array. The pre-scan
// has checked every index, so a bad one here means the two parsers read a line differently.
template <class T>
T element(const std::vector<T>& values, int index, const std::string& file, int line) {
    if (index < 0 || static_cast<std::size_t>(index) >= values.size())
        throw file_error(file, line,
                         "tinyobjloader resolved an index to " + std::to_string(index) +
                             ", outside the " + std::to_string(values.size()) +
                             " elements the pre-scan read");
    return values[static_cast<std::size_t>(index)];
}

}  // namespace

std::string utf8_or_latin1(const std::string& text) {
    // Valid UTF-8 (RFC 3629): no overlong forms, no surrogates, nothing above U+10FFFF.
    const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
    bool valid = true;
    for (std::size_t i = 0; i < text.size() && valid;) {
        const unsigned char b = byte(i);
        std::size_t length = 0;
        unsigned char low = 0x80, high = 0xBF;  // the second byte's range
        if (b < 0x80) {
            length = 1;
        } else if (b >= 0xC2 && b <= 0xDF) {
            length = 2;
        } else if (b >= 0xE0 && b <= 0xEF) {
            length = 3;
            if (b == 0xE0) low = 0xA0;
            if (b == 0xED) high = 0x9F;
        } else if (b >= 0xF0 && b <= 0xF4) {
            length = 4;
            if (b == 0xF0) low = 0x90;
            if (b == 0xF4) high = 0x8F;
        }
        valid = length > 0 && i + length <= text.size();
        for (std::size_t k = 1; valid && k < length; ++k) {
            const unsigned char c = byte(i + k);
            valid = k == 1 ? (c >= low && c <= high) : (c >= 0x80 && c <= 0xBF);
        }
        i += length;
    }
    if (valid) return text;
    std::string utf8;
    for (const char c : text) {
        const auto b = static_cast<unsigned char>(c);
        if (b < 0x80) {
            utf8.push_back(c);
        } else {
            utf8.push_back(static_cast<char>(0xC0 | (b >> 6)));
            utf8.push_back(static_cast<char>(0x80 | (b & 0x3F)));
        }
    }
    return utf8;
}

float ns_to_roughness(float ns) {
    const float alpha = std::sqrt(2.0f / (std::max(ns, 0.0f) + 2.0f));
    return std::sqrt(alpha);
}

int find_material(const Scene& scene, const std::string& name, TextureCache& cache) {
    for (; cache.materials_indexed < scene.materials.size(); ++cache.materials_indexed)
        cache.material_by_name.emplace(scene.materials[cache.materials_indexed].name,
                                       static_cast<int>(cache.materials_indexed));
    auto it = cache.material_by_name.find(name);
    return it == cache.material_by_name.end() ? -1 : it->second;
}

int intern_material(Scene& scene, const Material& material, const std::string& defined_at,
                    TextureCache& cache) {
    const int found = find_material(scene, material.name, cache);
    if (found >= 0) {
        if (scene.materials[static_cast<std::size_t>(found)] == material) return found;
        throw Error(defined_at + ": material '" + material.name +
                    "' differs from an earlier material of the same name (material names must "
                    "be unique in a scene)");
    }
    scene.materials.push_back(material);
    return static_cast<int>(scene.materials.size() - 1);
}

namespace {

// --- Meshes: tinyobjloader's faces to world-space triangles --------------------------------------

// What tinyobjloader reads of an OBJ: its v/vt/vn arrays (only their sizes are used), faces,
// materials and warnings.
struct TinyObjMesh {
    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    std::vector<tinyobj::material_t> materials;
    std::string warn;
};

// Parses the pre-scanned text with tinyobjloader (MTL files from the pre-scan), and checks that
// it read the same v, vt, vn and f statements as the pre-scan: its indices refer to its own
// v/vt/vn arrays, so the pre-scan's arrays must hold the same statements for the indices to
// carry over (and faces must match face_lines).
TinyObjMesh parse_with_tinyobj(const std::string& obj_path, const std::string& text,
                               const ObjScan& scan) {
    TinyObjMesh mesh;
    std::string err;
    std::istringstream stream(tinyobj_text(text));
    if (!tinyobj::LoadObj(&mesh.attrib, &mesh.shapes, &mesh.materials, &mesh.warn, &err, &stream,
                          /*readMatFn=*/nullptr, /*triangulate=*/false,
                          /*default_vcols_fallback=*/false))
        throw Error(obj_path + ": " + tinyobj_message(err));
    // tinyobjloader read the same statements: the same v, vt, vn counts, materials, and the
    // same face corners (its per-face corner counts are unsigned char, so only the flat list of
    // corners is compared).
    const tinyobj::attrib_t& attrib = mesh.attrib;
    std::size_t corner_count = 0;
    bool same_corners = true;
    for (const tinyobj::shape_t& shape : mesh.shapes) {
        for (const tinyobj::index_t& index : shape.mesh.indices) {
            if (corner_count < scan.corners.size()) {
                const ObjCorner& ours = scan.corners[corner_count];
                same_corners = same_corners && index.vertex_index == ours.vertex &&
                               index.texcoord_index == ours.texcoord &&
                               index.normal_index == ours.normal;
            }
            ++corner_count;
        }
    }
    if (attrib.vertices.size() != 3 * scan.positions.size() ||
        attrib.texcoords.size() != 2 * scan.texcoords.size() ||
        attrib.normals.size() != 3 * scan.normals.size() || corner_count != scan.corners.size() ||
        !same_corners)
        throw Error(
            obj_path + ": tinyobjloader read " + std::to_string(attrib.vertices.size() / 3) +
            " v, " + std::to_string(attrib.texcoords.size() / 2) + " vt, " +
            std::to_string(attrib.normals.size() / 3) + " vn, " + std::to_string(corner_count) +
            " face corners" + (same_corners ? "" : " (some of them different)") +
            ", the pre-scan " + std::to_string(scan.positions.size()) + ", " +
            std::to_string(scan.texcoords.size()) + ", " + std::to_string(scan.normals.size()) +
            " and " + std::to_string(scan.corners.size()));
    return mesh;
}

// Adds every material of the MTL files to the scene, in file order (a repeated definition is
// skipped); returns the scene's index of each of the pre-scan's materials.
std::vector<int> intern_mtl_materials(Scene& scene, const MtlScan& mtl, TextureCache& cache,
                                      const QuirkLog& log) {
    std::vector<int> material_index(mtl.materials.size(), -1);
    for (std::size_t m = 0; m < mtl.materials.size(); ++m) {
        const MtlMaterialInfo& info = mtl.materials[m];
        if (info.duplicate) continue;
        Material material = convert_material(scene, info, cache, log);
        material_index[m] = intern_material(scene, material, location(info.file, info.line), cache);
    }
    return material_index;
}

// The object-to-world transform of an instance transform; throws "<where>: ..." when it is
// singular or not finite.
ObjectToWorld instance_to_world(const glm::mat4& transform, const std::string& where) {
    const TransformCheck check = object_to_world(transform);
    if (check.singular || !check.finite)
        throw Error(where + ": the instance transform is singular or not finite");
    return check.to_world;
}

// Triangle (index[0], index[1], index[2]) from the pre-scan's arrays, in world space; uv (0,0)
// where a corner has no texture coordinates.
WorldTriangle world_triangle(const ObjCorner (&index)[3], const ObjScan& scan,
                             const ObjectToWorld& to_world, const std::string& obj_path, int line) {
    WorldTriangle t{};
    for (int c = 0; c < 3; ++c) {
        t.position[c] = to_world.point(element(scan.positions, index[c].vertex, obj_path, line));
        t.has_normal[c] = index[c].normal >= 0;
        if (t.has_normal[c])
            t.normal[c] = to_world.normal(element(scan.normals, index[c].normal, obj_path, line));
        t.uv[c] = index[c].texcoord >= 0
                      ? element(scan.texcoords, index[c].texcoord, obj_path, line)
                      : glm::vec2(0.0f);
    }
    return t;
}

// The material of faces without one (no usemtl, or an undefined one): "default" (Material's
// defaults), or "default-2", "default-3", ... when an MTL file defines a different "default".
int default_material(Scene& scene, const std::string& defined_at, TextureCache& cache) {
    Material fallback;
    for (int k = 1;; ++k) {
        fallback.name = k == 1 ? "default" : "default-" + std::to_string(k);
        const int found = find_material(scene, fallback.name, cache);
        if (found < 0 || scene.materials[static_cast<std::size_t>(found)] == fallback)
            return intern_material(scene, fallback, defined_at, cache);
    }
}

// Appends the faces' triangles to the scene in face order, each face split by
// triangulate_polygon, with the material its usemtl gave it (default_material where none).
// Zero-area (or non-finite) triangles are dropped, counted and the first max_listed_warnings
// of them listed; returns how many were dropped.
std::int64_t add_obj_triangles(Scene& scene, TextureCache& cache, const std::string& obj_path,
                               const ObjScan& scan, const std::vector<int>& material_index,
                               const ObjectToWorld& to_world) {
    SceneLoadStats& stats = scene.load_stats;
    int fallback = -1;
    std::int64_t dropped_here = 0;
    std::int64_t not_simple = 0;
    std::int64_t ear_budget = ear_clipping_budget;
    std::vector<glm::vec3> polygon;
    for (std::size_t face = 0; face < scan.face_starts.size(); ++face) {
        const std::size_t first = scan.face_starts[face];
        const std::size_t corners = (face + 1 < scan.face_starts.size() ? scan.face_starts[face + 1]
                                                                        : scan.corners.size()) -
                                    first;
        const int line = scan.face_lines[face];
        const int source_material = scan.face_materials[face];
        int material =
            source_material >= 0 ? material_index[static_cast<std::size_t>(source_material)] : -1;
        if (material < 0) {
            if (fallback < 0) fallback = default_material(scene, location(obj_path, line), cache);
            material = fallback;
        }
        // Triangulated in object space: the transform does not change which corners form
        // the triangles.
        polygon.clear();
        for (std::size_t k = 0; k < corners; ++k)
            polygon.push_back(
                element(scan.positions, scan.corners[first + k].vertex, obj_path, line));
        PolygonSplit split = PolygonSplit::triangle;
        const std::vector<std::array<int, 3>> triangles =
            triangulate_polygon(polygon, &split, &ear_budget);
        if (corners > 3) ++stats.polygons_triangulated;
        if (split == PolygonSplit::ear_clipped || split == PolygonSplit::not_simple)
            ++stats.concave_polygons;
        if (split == PolygonSplit::not_simple && ++not_simple <= max_listed_warnings)
            stats.warnings.push_back(location(obj_path, line) +
                                     ": concave polygon that ear clipping cannot split (its "
                                     "edges cross, it has more than " +
                                     std::to_string(max_ear_clipping_corners) +
                                     " corners, or the file's ear-clipping budget is spent); "
                                     "fanned instead");
        for (const std::array<int, 3>& corner : triangles) {
            ObjCorner index[3] = {scan.corners[first + static_cast<std::size_t>(corner[0])],
                                  scan.corners[first + static_cast<std::size_t>(corner[1])],
                                  scan.corners[first + static_cast<std::size_t>(corner[2])]};
            if (to_world.mirror) std::swap(index[1], index[2]);
            WorldTriangle t = world_triangle(index, scan, to_world, obj_path, line);
            if (!append_triangle(scene, t, material, obj_path) &&
                ++dropped_here <= max_listed_warnings)
                stats.warnings.push_back(location(obj_path, line) + ": zero-area triangle dropped");
        }
    }
    if (not_simple > max_listed_warnings)
        stats.warnings.push_back(obj_path + ": " + std::to_string(not_simple) +
                                 " concave polygons were fanned (the first " +
                                 std::to_string(max_listed_warnings) + " are listed)");
    return dropped_here;
}

}  // namespace

void load_obj_into(Scene& scene, const std::string& obj_path, const glm::mat4& transform,
                   TextureCache& cache, const std::string& referenced_at, bool strict) {
    // Read and pre-scan.
    std::error_code ec;
    if (!std::filesystem::is_regular_file(obj_path, ec))
        throw Error((referenced_at.empty() ? obj_path : referenced_at) + ": OBJ file '" + obj_path +
                    "' not found");
    SceneLoadStats& stats = scene.load_stats;
    int malformed_numbers = 0;
    const QuirkLog log{strict, &stats.warnings, &malformed_numbers};
    const std::string text = checked_text(read_file(obj_path), obj_path, stats.warnings);
    const ObjScan scan = scan_obj(obj_path, text, log);

    const TinyObjMesh mesh = parse_with_tinyobj(obj_path, text, scan);
    // Materials: every material of the MTL files, in file order; faces without one get the
    // default material.
    const std::vector<int> material_index = intern_mtl_materials(scene, scan.mtl, cache, log);
    const ObjectToWorld to_world =
        instance_to_world(transform, referenced_at.empty() ? obj_path : referenced_at);
    const std::int64_t dropped_here =
        add_obj_triangles(scene, cache, obj_path, scan, material_index, to_world);

    note_dropped_total(scene, obj_path, dropped_here);
    if (malformed_numbers > max_listed_warnings)
        stats.warnings.push_back(obj_path + ": " + std::to_string(malformed_numbers) +
                                 " malformed numbers read from their valid start (the first " +
                                 std::to_string(max_listed_warnings) + " are listed)");
    if (scan.points > 0 || scan.lines > 0) {
        stats.points_ignored += scan.points;
        stats.lines_ignored += scan.lines;
        stats.warnings.push_back(obj_path + ": " + std::to_string(scan.points) +
                                 " points (p) and " + std::to_string(scan.lines) +
                                 " lines (l) ignored: fovref renders triangles only");
    }
    // tinyobjloader's own warnings, one per line.
    std::istringstream warnings(mesh.warn);
    for (std::string line; std::getline(warnings, line);)
        if (!line.empty()) stats.warnings.push_back(obj_path + ": " + line);
}

void load_obj_into(Scene& scene, const std::string& obj_path, const glm::mat4& transform,
                   const SceneLoadOptions& options) {
    TextureCache cache;
    load_obj_into(scene, obj_path, transform, cache, "", options.strict_obj);
}

}  // namespace fovref
