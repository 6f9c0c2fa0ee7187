#pragma once
// Frame numbers and file-name patterns of rendered sequences (docs/cli.md "batch").
#include <optional>
#include <string>
#include <vector>

namespace decalcomp {

// "1-240", "1-240x2" (every 2nd), "1,5,10-20", "-5--1": frames in the order given, each once.
// Throws Error(Usage) naming the bad part of `spec`.
std::vector<int> parseFrameRange(const std::string& spec);

// A path with exactly one frame token: a run of '#' (as many digits, zero-padded: "####" -> 0007)
// or a printf-style "%d" / "%0Nd". Negative frames print a '-' before the padded digits, as printf.
class FramePattern {
public:
    FramePattern() = default;
    explicit FramePattern(const std::string& pattern);  // Error(Usage) without exactly one token
    static bool hasToken(const std::string& text);       // any '#' run or %d / %0Nd

    std::string path(int frame) const;
    // The frame a path stands for, when it is exactly this pattern's path for that frame.
    std::optional<int> match(const std::string& path) const;
    const std::string& text() const { return text_; }

private:
    std::string text_, prefix_, suffix_;
    int width_ = 0;
};

// Every frame whose file exists, by listing the folder of `input` (the token must be in the file
// name). Sorted; throws Error(Input) when none matches.
std::vector<int> discoverFrames(const FramePattern& input);

}  // namespace decalcomp
