#pragma once
// Outputs are written whole or not at all: a writer fills a temporary file
// beside the destination, and only a successful commit() renames it into
// place (rename is atomic within one file system). A writer that is
// destroyed without commit() — an exception — removes its temporary file,
// an interrupt (install_interrupt_cleanup) too, and what a killed process
// left (.<name>.partial-<pid>.<ext> of a process that no longer runs) is
// removed by the next writer to the same destination, so no half-written
// output is ever left behind.

#include <string>

namespace jade {

// On SIGINT or SIGTERM: remove every AtomicFile's temporary file that is
// still open, say so in one line on stderr and exit with 128 + the signal
// (130, 143). Outputs already committed are complete and stay. The one
// piece of process-wide state in the program, because signals and files on
// disk are process-wide: the handler can only reach the temporary files
// through a fixed table (it may not allocate or lock). Call once, from main.
void install_interrupt_cleanup();

class AtomicFile {
public:
    explicit AtomicFile(std::string destination);
    ~AtomicFile();
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    // Where the writer should put the bytes. Keeps the destination's
    // extension, since some writers pick the format from it.
    const std::string& temp_path() const { return temp_; }
    const std::string& destination() const { return destination_; }

    // Moves the finished temporary file onto the destination.
    void commit();

private:
    std::string destination_;
    std::string temp_;
    bool committed_ = false;
    int slot_ = -1;  // its entry in the interrupt handler's table (-1: none free)
};

// Writes `text` (or any bytes, e.g. a .glb) to `path` through an AtomicFile,
// checking the stream after its last flush and its close (where a full disk
// shows).
void write_text_file(const std::string& path, const std::string& text);

// Size of a file in bytes (0 when it does not exist).
unsigned long long file_size(const std::string& path);

// Throws jade::Error naming `path` when the folder it would be written to does
// not exist, so a command can refuse before doing its work rather than after.
void require_output_folder(const std::string& path);

}  // namespace jade
