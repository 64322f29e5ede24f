#pragma once
// Some codecs (libpng) print their own complaints on stderr before
// OpenImageIO reports the same problem through geterror(). The user must see
// one line, so while a decoder runs stderr is pointed at /dev/null. Images
// are read before any worker thread starts, so nothing else is silenced.

namespace jade {

class QuietStderr {
public:
    QuietStderr();
    ~QuietStderr();
    QuietStderr(const QuietStderr&) = delete;
    QuietStderr& operator=(const QuietStderr&) = delete;

private:
    int saved_ = -1;  // the real stderr, restored on destruction
};

}  // namespace jade
