// Source lines of JSON values, for error messages (SPEC §2: "reported with file and line").
//
// nlohmann::json parses a document but forgets where each value was. The locator walks the same
// text once with a tiny tokenizer that tracks the JSON pointer (RFC 6901) of the value it is in,
// and records for every value the line of its key (array elements: of the value) and the line
// where the value starts. The scene loader validates the parsed document and, on a semantic
// error, asks the locator for the line of the offending pointer.
//
// The walk also finds what nlohmann accepts or rejects without a position: duplicate keys
// (nlohmann keeps the last one silently) and numbers that overflow binary64 (nlohmann throws
// out_of_range without a byte offset). Both are thrown as fovref::Error with file:line.
#pragma once

#include <charconv>
#include <cstddef>
#include <map>
#include <string>
#include <string_view>

#include "ref/core/error.h"

namespace fovref {

struct JsonLocation {
    int key_line = 0;              ///< line of the member's key; for array elements, of the value
    int value_line = 0;            ///< line of the value's first character
    std::size_t value_offset = 0;  ///< byte offset of the value's first character
};

/// "file:line:column: JSON syntax error: message" (line 0: no position).
Error json_syntax_error(const std::string& file, int line, int column, const std::string& message);

class JsonLocator {
public:
    /// Walks `text`, which should be valid JSON (parse it with nlohmann first; anything the
    /// tokenizer cannot follow is reported as a syntax error with line and column). Throws
    /// fovref::Error naming `file` on duplicate keys, numbers beyond binary64 and nesting deeper
    /// than max_depth.
    JsonLocator(const std::string& text, const std::string& file);

    /// Location of the value at `pointer` ("" = the root, "/camera/position/1"); zero lines when
    /// the pointer names no value in the text.
    JsonLocation find(const std::string& pointer) const;

    /// The binary32 nearest to the number at `pointer`, parsed from the document's own text with
    /// std::from_chars (correctly rounded; nlohmann reads binary64, and rounding that again to
    /// float can differ by one ulp for decimals close to a float midpoint). False when the pointer
    /// names no number.
    bool number_as_float(const std::string& pointer, float& value) const;

    static constexpr int max_depth = 256;

private:
    std::string text_;
    std::map<std::string, JsonLocation> locations_;
};

/// JSON pointer of a member or element: escapes '~' as "~0" and '/' as "~1" (RFC 6901).
std::string json_pointer_member(const std::string& pointer, const std::string& key);
std::string json_pointer_element(const std::string& pointer, std::size_t index);

/// 1-based line and column of byte `offset` (0-based) in `text`; offsets past the end point at
/// the last character.
void json_line_column(const std::string& text, std::size_t offset, int& line, int& column);

/// Throws fovref::Error naming `file` and the line when arrays and objects in `text` nest deeper
/// than `max_depth` (strings skipped, escapes honoured). Every JSON reader calls it before
/// parsing, so hostile nesting is refused in linear time and constant stack.
void check_json_nesting(std::string_view text, const std::string& file,
                        int max_depth = JsonLocator::max_depth);

/// check_json_nesting, then Json::parse (nlohmann::json or ordered_json), with a syntax error
/// turned into fovref::Error "file:line:column: JSON syntax error: ..." and a number beyond
/// binary64 into "file:line: number ... is out of range".
template <class Json>
Json parse_json_document(const std::string& text, const std::string& file) {
    check_json_nesting(text, file);
    try {
        return Json::parse(text);
    } catch (const typename Json::parse_error& e) {
        int line = 0, column = 0;
        json_line_column(text, e.byte > 0 ? e.byte - 1 : 0, line, column);
        std::string message = e.what();
        const std::size_t detail = message.find(": ", message.find("column"));
        if (detail != std::string::npos) message = message.substr(detail + 2);
        throw json_syntax_error(file, line, column, message);
    } catch (const typename Json::exception& e) {
        JsonLocator locate(text, file);  // throws the located error (a number out of range)
        throw json_syntax_error(file, 0, 0, e.what());
    }
}

}  // namespace fovref
