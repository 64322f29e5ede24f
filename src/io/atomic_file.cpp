#include "jade/io/atomic_file.h"

#include "jade/core/error.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace jade {

namespace fs = std::filesystem;

void require_output_folder(const std::string& path) {
    const fs::path dest(path);
    const fs::path dir = dest.parent_path().empty() ? fs::path(".") : dest.parent_path();
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) fail_file(path, "the folder '" + dir.string() + "' does not exist");
}

AtomicFile::AtomicFile(std::string destination) : destination_(std::move(destination)) {
    require_output_folder(destination_);
    const fs::path dest(destination_);
    const fs::path dir = dest.parent_path().empty() ? fs::path(".") : dest.parent_path();
    // Hidden, unique per process, same folder (so the final rename is atomic),
    // same extension (writers choose the format from it).
    temp_ = (dir / ("." + dest.stem().string() + ".partial-" + std::to_string(::getpid()) +
                    dest.extension().string()))
                .string();
}

AtomicFile::~AtomicFile() {
    if (!committed_) std::remove(temp_.c_str());
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
        std::ofstream out(file.temp_path(), std::ios_base::out | std::ios_base::trunc);
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
