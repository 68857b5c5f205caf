#pragma once
// Helpers shared by the tests.

#include <cctype>
#include <string>

namespace quadcage::test {

/// `text` with every character that is not a letter or digit replaced by '_' (a valid GoogleTest
/// parameter name or file-name part).
inline std::string identifier(std::string text) {
    for (char& ch : text)
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
    return text;
}

}  // namespace quadcage::test
