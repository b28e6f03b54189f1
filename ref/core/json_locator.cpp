#include "ref/core/json_locator.h"

#include <cmath>
#include <cstdlib>
#include <set>
#include <system_error>

#include "ref/core/error.h"

namespace fovref {

std::string json_pointer_member(const std::string& pointer, const std::string& key) {
    std::string result = pointer + "/";
    for (char c : key) {
        if (c == '~') {
            result += "~0";
        } else if (c == '/') {
            result += "~1";
        } else {
            result += c;
        }
    }
    return result;
}

std::string json_pointer_element(const std::string& pointer, std::size_t index) {
    return pointer + "/" + std::to_string(index);
}

void json_line_column(const std::string& text, std::size_t offset, int& line, int& column) {
    if (!text.empty() && offset >= text.size()) offset = text.size() - 1;
    line = 1;
    std::size_t line_start = 0;
    for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
        if (text[i] == '\n') {
            ++line;
            line_start = i + 1;
        }
    }
    column = static_cast<int>(offset - line_start) + 1;
}

Error json_syntax_error(const std::string& file, int line, int column, const std::string& message) {
    if (line <= 0) return Error(file + ": JSON syntax error: " + message);
    return Error(file + ":" + std::to_string(line) + ":" + std::to_string(column) +
                 ": JSON syntax error: " + message);
}

void check_json_nesting(std::string_view text, const std::string& file, int max_depth) {
    int depth = 0, line = 1;
    bool in_string = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (c == '\n') ++line;
        if (in_string) {
            if (c == '\\')
                ++i;  // the escaped character cannot end the string
            else if (c == '"')
                in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > max_depth)
                throw file_error(
                    file, line, "JSON nested deeper than " + std::to_string(max_depth) + " levels");
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
}

namespace {

// Walk the JSON text (RFC 8259 grammar) recording each value's pointer and lines.
class Walker {
public:
    Walker(const std::string& text, const std::string& file,
           std::map<std::string, JsonLocation>& locations)
        : text_(text), file_(file), locations_(locations) {}

    void document() {
        if (text_.compare(0, 3, "\xEF\xBB\xBF") == 0)
            pos_ = 3;  // UTF-8 byte order mark (nlohmann skips it)
        skip_space();
        value("", line_, 0);
        skip_space();
        if (pos_ < text_.size()) syntax_error("unexpected text after the document");
    }

private:
    [[noreturn]] void syntax_error(const std::string& what) const {
        int line = 0, column = 0;
        json_line_column(text_, pos_, line, column);
        throw Error(file_ + ":" + std::to_string(line) + ":" + std::to_string(column) +
                    ": JSON syntax error: " + what);
    }

    char peek() const { return pos_ < text_.size() ? text_[pos_] : '\0'; }

    void skip_space() {
        while (pos_ < text_.size()) {
            char c = text_[pos_];
            if (c == '\n') {
                ++line_;
            } else if (c != ' ' && c != '\t' && c != '\r') {
                return;
            }
            ++pos_;
        }
    }

    void expect(char c) {
        if (peek() != c) syntax_error(std::string("expected '") + c + "'");
        ++pos_;
    }

    // Append code point `cp` as UTF-8 (what nlohmann stores for \uXXXX escapes).
    static void append_utf8(std::string& out, unsigned cp) {
        if (cp < 0x80) {
            out += static_cast<char>(cp);
        } else if (cp < 0x800) {
            out += static_cast<char>(0xC0 | (cp >> 6));
            out += static_cast<char>(0x80 | (cp & 0x3F));
        } else if (cp < 0x10000) {
            out += static_cast<char>(0xE0 | (cp >> 12));
            out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
            out += static_cast<char>(0x80 | (cp & 0x3F));
        } else {
            out += static_cast<char>(0xF0 | (cp >> 18));
            out += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
            out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
            out += static_cast<char>(0x80 | (cp & 0x3F));
        }
    }

    unsigned hex4() {
        if (pos_ + 4 > text_.size()) syntax_error("truncated \\u escape");
        unsigned value = 0;
        for (int k = 0; k < 4; ++k) {
            char c = text_[pos_++];
            unsigned digit = 0;
            if (c >= '0' && c <= '9') {
                digit = static_cast<unsigned>(c - '0');
            } else if (c >= 'a' && c <= 'f') {
                digit = static_cast<unsigned>(c - 'a' + 10);
            } else if (c >= 'A' && c <= 'F') {
                digit = static_cast<unsigned>(c - 'A' + 10);
            } else {
                syntax_error("bad \\u escape");
            }
            value = value * 16 + digit;
        }
        return value;
    }

    // A string token, decoded (keys must match nlohmann's decoded keys).
    std::string string_token() {
        expect('"');
        std::string out;
        while (true) {
            if (pos_ >= text_.size()) syntax_error("unterminated string");
            char c = text_[pos_++];
            if (c == '"') return out;
            if (c != '\\') {
                out += c;
                continue;
            }
            char e = peek();
            ++pos_;
            switch (e) {
                case '"': out += '"'; break;
                case '\\': out += '\\'; break;
                case '/': out += '/'; break;
                case 'b': out += '\b'; break;
                case 'f': out += '\f'; break;
                case 'n': out += '\n'; break;
                case 'r': out += '\r'; break;
                case 't': out += '\t'; break;
                case 'u': {
                    unsigned cp = hex4();
                    // A high surrogate followed by \uDC00..\uDFFF is one code point.
                    if (cp >= 0xD800 && cp < 0xDC00 && peek() == '\\' && pos_ + 1 < text_.size() &&
                        text_[pos_ + 1] == 'u') {
                        pos_ += 2;
                        unsigned low = hex4();
                        cp = 0x10000 + ((cp - 0xD800) << 10) + (low - 0xDC00);
                    }
                    append_utf8(out, cp);
                    break;
                }
                default: syntax_error("bad escape in string");
            }
        }
    }

    void number_token() {
        const std::size_t start = pos_;
        while (pos_ < text_.size()) {
            char c = text_[pos_];
            if ((c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.' || c == 'e' ||
                c == 'E') {
                ++pos_;
            } else {
                break;
            }
        }
        if (pos_ == start) syntax_error("expected a value");
        // nlohmann rejects numbers beyond binary64 (out_of_range.406) without a position.
        std::string token = text_.substr(start, pos_ - start);
        double value = std::strtod(token.c_str(), nullptr);
        if (std::isinf(value))
            throw file_error(file_, line_, "number " + token + " is out of range");
    }

    void value(const std::string& pointer, int key_line, int depth) {
        if (depth > JsonLocator::max_depth)
            throw file_error(file_, line_,
                             "JSON nested deeper than " + std::to_string(JsonLocator::max_depth));
        locations_[pointer] = JsonLocation{key_line, line_, pos_};
        char c = peek();
        if (c == '{') {
            ++pos_;
            std::set<std::string> keys;
            skip_space();
            if (peek() == '}') {
                ++pos_;
                return;
            }
            while (true) {
                skip_space();
                const int member_line = line_;
                std::string key = string_token();
                if (!keys.insert(key).second)
                    throw file_error(file_, member_line, "duplicate key \"" + key + "\"");
                skip_space();
                expect(':');
                skip_space();
                value(json_pointer_member(pointer, key), member_line, depth + 1);
                skip_space();
                if (peek() == ',') {
                    ++pos_;
                    continue;
                }
                expect('}');
                return;
            }
        }
        if (c == '[') {
            ++pos_;
            skip_space();
            if (peek() == ']') {
                ++pos_;
                return;
            }
            for (std::size_t index = 0;; ++index) {
                skip_space();
                value(json_pointer_element(pointer, index), line_, depth + 1);
                skip_space();
                if (peek() == ',') {
                    ++pos_;
                    continue;
                }
                expect(']');
                return;
            }
        }
        if (c == '"') {
            string_token();
            return;
        }
        if (c == 't' || c == 'f' || c == 'n') {
            while (pos_ < text_.size() && text_[pos_] >= 'a' && text_[pos_] <= 'z') ++pos_;
            return;
        }
        number_token();
    }

    const std::string& text_;
    const std::string& file_;
    std::map<std::string, JsonLocation>& locations_;
    std::size_t pos_ = 0;
    int line_ = 1;
};

}  // namespace

JsonLocator::JsonLocator(const std::string& text, const std::string& file) : text_(text) {
    Walker(text, file, locations_).document();
}

bool JsonLocator::number_as_float(const std::string& pointer, float& value) const {
    auto it = locations_.find(pointer);
    if (it == locations_.end()) return false;
    std::size_t begin = it->second.value_offset;
    while (begin < text_.size() && (text_[begin] == ' ' || text_[begin] == '\t' ||
                                    text_[begin] == '\n' || text_[begin] == '\r'))
        ++begin;
    const char* first = text_.data() + begin;
    const char* last = text_.data() + text_.size();
    const auto [end, ec] = std::from_chars(first, last, value);
    return ec == std::errc() && end != first;
}

JsonLocation JsonLocator::find(const std::string& pointer) const {
    auto it = locations_.find(pointer);
    return it == locations_.end() ? JsonLocation{} : it->second;
}

}  // namespace fovref
