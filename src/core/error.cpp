#include "jade/core/error.h"

#include <algorithm>

namespace jade {

namespace {
// The user sees exactly one line: third-party messages sometimes carry newlines.
std::string one_line(std::string s) {
    std::replace(s.begin(), s.end(), '\n', ' ');
    std::replace(s.begin(), s.end(), '\r', ' ');
    while (!s.empty() && s.back() == ' ') s.pop_back();
    return s;
}
}  // namespace

Error::Error(const std::string& message) : std::runtime_error(one_line(message)) {}

void fail_file(const std::string& path, const std::string& problem) {
    throw Error(path + ": " + problem);
}

}  // namespace jade
