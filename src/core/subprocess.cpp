#include "jade/core/subprocess.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>

extern char** environ;

namespace jade {

namespace {

// Closes both ends of a pipe and the spawn's file actions on every way out.
struct SpawnPlumbing {
    int out[2] = {-1, -1};
    posix_spawn_file_actions_t actions{};
    bool actions_ready = false;
    ~SpawnPlumbing() {
        for (int fd : out)
            if (fd >= 0) ::close(fd);
        if (actions_ready) posix_spawn_file_actions_destroy(&actions);
    }
};

}  // namespace

ProcessResult run_program(const std::string& program, const std::vector<std::string>& args) {
    ProcessResult result;
    SpawnPlumbing p;
    if (::pipe2(p.out, O_CLOEXEC) != 0) return result;
    if (posix_spawn_file_actions_init(&p.actions) != 0) return result;
    p.actions_ready = true;
    // The child's stdout is the pipe's write end (dup2 clears its
    // close-on-exec); stdin and stderr are /dev/null, so that a library's
    // complaints about a damaged file do not reach the user's terminal.
    posix_spawn_file_actions_adddup2(&p.actions, p.out[1], STDOUT_FILENO);
    posix_spawn_file_actions_addopen(&p.actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&p.actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);

    std::vector<std::string> words{program};
    words.insert(words.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& w : words) argv.push_back(w.data());
    argv.push_back(nullptr);

    pid_t pid = -1;
    if (posix_spawn(&pid, program.c_str(), &p.actions, nullptr, argv.data(), environ) != 0) return result;
    result.started = true;
    ::close(p.out[1]);
    p.out[1] = -1;
    char buf[4096];
    for (;;) {
        const ssize_t n = ::read(p.out[0], buf, sizeof buf);
        if (n > 0) result.output.append(buf, std::size_t(n));
        else if (n == 0 || errno != EINTR) break;
    }
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (WIFEXITED(status)) result.exit_code = WEXITSTATUS(status);
    if (WIFSIGNALED(status)) result.signal = WTERMSIG(status);
    return result;
}

std::string own_executable_dir() {
    std::error_code ec;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
    return ec ? std::string() : self.parent_path().string();
}

}  // namespace jade
