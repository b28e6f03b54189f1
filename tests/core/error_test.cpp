#include <doctest/doctest.h>

#include <cstddef>
#include <string>

#include "ref/core/error.h"

using namespace fovref;

namespace {

std::string check_eq_message(std::size_t texels, std::size_t expected) {
    try {
        FOVREF_CHECK_EQ(texels, expected, "the texel count");
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_CASE("FOVREF_CHECK_EQ prints both sides, the expressions, the message and the place") {
    CHECK(check_eq_message(853, 853).empty());
    const std::string message = check_eq_message(852, 853);
    CHECK(message.find("internal check failed: texels == expected (852 != 853; the texel count)") !=
          std::string::npos);
    CHECK(message.find("error_test.cpp:") != std::string::npos);
    // Floats round-trip exactly, so two values one ulp apart are told apart.
    CHECK(check_value_text(1.0f) == "1");
    CHECK(check_value_text(0.1f) == "0.100000001");
    CHECK(check_value_text(0.1) == "0.10000000000000001");
    CHECK(check_value_text(-3) == "-3");
    CHECK(check_value_text(std::string("ab")) == "'ab'");
    CHECK(check_value_text(true) == "true");
    // Each side is evaluated once.
    int calls = 0;
    auto next = [&calls] { return ++calls; };
    CHECK_THROWS_AS(FOVREF_CHECK_EQ(next(), 5, "once"), Error);
    CHECK(calls == 1);
}
