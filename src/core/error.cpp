#include "jade/core/error.h"

#include <algorithm>

namespace jade {

std::string one_line(const std::string& text) {
    // The user sees exactly one line: third-party messages sometimes carry
    // newlines, and a corrupt file's can quote gigabytes of it.
    constexpr std::size_t kLongest = 400;
    std::string s = text.substr(0, kLongest + 1);
    std::replace(s.begin(), s.end(), '\n', ' ');
    std::replace(s.begin(), s.end(), '\r', ' ');
    if (s.size() > kLongest) s = s.substr(0, kLongest) + "...";
    while (!s.empty() && s.back() == ' ') s.pop_back();
    return s;
}

Error::Error(const std::string& message) : std::runtime_error(one_line(message)) {}

void fail_file(const std::string& path, const std::string& problem) {
    throw Error(path + ": " + problem);
}

}  // namespace jade
