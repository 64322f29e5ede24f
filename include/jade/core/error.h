#pragma once
// Errors that reach the user. Every failure the user can cause (a missing or
// corrupt file, a nonsense parameter) is thrown as jade::Error with a message
// that names the file or the parameter and the problem, in one line. The
// command-line front end prints it and exits with code 2.

#include <stdexcept>
#include <string>

namespace jade {

class Error : public std::runtime_error {
public:
    explicit Error(const std::string& message);
};

// A message made fit for one line: newlines as spaces, at most 400
// characters (a corrupt file's message can quote anything). Every Error's
// message passes through it.
std::string one_line(const std::string& text);

// Message for a problem with a named file: "<path>: <problem>".
[[noreturn]] void fail_file(const std::string& path, const std::string& problem);

}  // namespace jade
