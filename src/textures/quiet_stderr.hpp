#pragma once
// libpng (under OpenImageIO) prints "libpng error: ..." to stderr before OIIO reports the same
// failure; decalcomp's errors are one line of its own, so fd 2 is pointed at /dev/null while an
// image library decodes. Process-wide, so it is meant for decoding before worker threads start
// (scene loading); a mutex keeps two decoders from restoring each other's descriptors.
namespace decalcomp {

class QuietStderr {
public:
    QuietStderr();
    ~QuietStderr();
    QuietStderr(const QuietStderr&) = delete;
    QuietStderr& operator=(const QuietStderr&) = delete;

private:
    int saved_ = -1;
};

}  // namespace decalcomp
