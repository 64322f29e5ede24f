#pragma once
// A program run in a process of its own, its standard output captured.
//
// Started with posix_spawn (a new program image), never a bare fork: after
// fork() a multithreaded process's child holds copies of every lock and
// thread pool the other threads were using, and a library such as TBB can
// wait forever in it for a worker thread that does not exist there.

#include <string>
#include <vector>

namespace jade {

struct ProcessResult {
    bool started = false;     // false: the program could not be started (nothing else is set)
    int exit_code = -1;       // the code it exited with, or -1 when a signal ended it
    int signal = 0;           // the signal that ended it, or 0
    std::string output;       // everything it wrote to standard output
};

// Runs `program` with `args` (argv[1..]), standard input and error on
// /dev/null, the environment inherited; waits for it to end.
ProcessResult run_program(const std::string& program, const std::vector<std::string>& args);

// The directory of this process's own executable (/proc/self/exe), or an
// empty string where it cannot be known.
std::string own_executable_dir();

}  // namespace jade
