#include "jade/io/atomic_file.h"

#include "jade/core/error.h"

#include <array>
#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <signal.h>
#include <unistd.h>

namespace jade {

namespace fs = std::filesystem;

void require_output_folder(const std::string& path) {
    const fs::path dest(path);
    const fs::path dir = dest.parent_path().empty() ? fs::path(".") : dest.parent_path();
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) fail_file(path, "the folder '" + dir.string() + "' does not exist");
}

namespace {

// The temporary files the interrupt handler removes: a fixed table of
// paths, each published by its `state` (0 free, 1 being written, 2 ready),
// so that the handler reads only complete paths and allocates nothing.
constexpr int kSlots = 16;
constexpr std::size_t kPathBytes = 4096;
struct TempSlot {
    std::atomic<int> state{0};
    char path[kPathBytes];
};
std::array<TempSlot, kSlots> temp_slots;

int register_temp(const std::string& path) {
    if (path.size() >= kPathBytes) return -1;
    for (int i = 0; i < kSlots; ++i) {
        int expected = 0;
        if (temp_slots[i].state.compare_exchange_strong(expected, 1)) {
            std::memcpy(temp_slots[i].path, path.c_str(), path.size() + 1);
            temp_slots[i].state.store(2);
            return i;
        }
    }
    return -1;  // full: that file is then removed only by unwinding
}

void unregister_temp(int slot) {
    if (slot >= 0) temp_slots[slot].state.store(0);
}

extern "C" void remove_temps_and_exit(int sig) {
    for (TempSlot& s : temp_slots)
        if (s.state.load() == 2) ::unlink(s.path);
    const char* text = sig == SIGINT ? "jaderender: interrupted (SIGINT); temporary files removed\n"
                                     : "jaderender: terminated (SIGTERM); temporary files removed\n";
    [[maybe_unused]] const ssize_t n = ::write(2, text, std::strlen(text));
    ::_exit(128 + sig);
}

// "." + stem + ".partial-" + pid + extension, beside the destination.
std::string temp_name(const fs::path& dest, long pid) {
    return "." + dest.stem().string() + ".partial-" + std::to_string(pid) + dest.extension().string();
}

// Temporary files for this destination left by processes that no longer
// run (killed by SIGKILL, a power cut): theirs to remove, nobody's now.
void remove_stale_temps(const fs::path& dir, const fs::path& dest) {
    const std::string prefix = "." + dest.stem().string() + ".partial-";
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
        const std::string name = entry.path().filename().string();
        if (name.rfind(prefix, 0) != 0) continue;
        const std::string rest = name.substr(prefix.size());
        char* end = nullptr;
        const long pid = std::strtol(rest.c_str(), &end, 10);
        if (pid <= 0 || end == rest.c_str() || name != temp_name(dest, pid)) continue;
        if (::kill(pid_t(pid), 0) != 0 && errno == ESRCH) fs::remove(entry.path(), ec);
    }
}

}  // namespace

void install_interrupt_cleanup() {
    struct sigaction action {};
    action.sa_handler = remove_temps_and_exit;
    sigemptyset(&action.sa_mask);
    ::sigaction(SIGINT, &action, nullptr);
    ::sigaction(SIGTERM, &action, nullptr);
}

AtomicFile::AtomicFile(std::string destination) : destination_(std::move(destination)) {
    require_output_folder(destination_);
    const fs::path dest(destination_);
    const fs::path dir = dest.parent_path().empty() ? fs::path(".") : dest.parent_path();
    remove_stale_temps(dir, dest);
    // Hidden, unique per process, same folder (so the final rename is atomic),
    // same extension (writers choose the format from it).
    temp_ = (dir / temp_name(dest, long(::getpid()))).string();
    slot_ = register_temp(temp_);
}

AtomicFile::~AtomicFile() {
    if (!committed_) std::remove(temp_.c_str());
    unregister_temp(slot_);
}

void AtomicFile::commit() {
    if (std::rename(temp_.c_str(), destination_.c_str()) != 0) {
        const std::string why = std::strerror(errno);
        std::remove(temp_.c_str());
        fail_file(destination_, "cannot write: " + why);
    }
    committed_ = true;
}

void write_text_file(const std::string& path, const std::string& text) {
    AtomicFile file(path);
    {
        std::ofstream out(file.temp_path(), std::ios_base::out | std::ios_base::trunc | std::ios_base::binary);
        out << text;
        out.flush();  // a full disk shows at the flush, not at <<
        const bool written = bool(out);
        out.close();
        if (!written || out.fail()) fail_file(path, std::string("cannot write: ") + std::strerror(errno));
    }
    file.commit();
}

unsigned long long file_size(const std::string& path) {
    std::error_code ec;
    const auto n = fs::file_size(path, ec);
    return ec ? 0 : static_cast<unsigned long long>(n);
}

}  // namespace jade
