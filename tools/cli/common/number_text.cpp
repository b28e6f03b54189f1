#include "tools/cli/common/number_text.h"

#include <cmath>
#include <cstdio>

namespace fovref {

std::string number_text(double v, const char* format, const char* nan) {
    if (nan && std::isnan(v)) return nan;
    char text[64];
    std::snprintf(text, sizeof text, format, v);
    return text;
}

}  // namespace fovref
