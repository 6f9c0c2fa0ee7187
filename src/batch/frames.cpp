// Frame ranges, frame-number patterns, discovery of existing frames, and shards of a range.
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <climits>
#include <filesystem>
#include <set>

#include "decalcomp/batch.hpp"
#include "decalcomp/error.hpp"

namespace decalcomp {

namespace fs = std::filesystem;

namespace {

Error usage(const std::string& message) { return Error(ErrorKind::Usage, message); }

// A whole (optionally negative) integer; nullopt for anything else, including overflow.
std::optional<long long> parseInteger(std::string_view text) {
    if (text.empty()) return std::nullopt;
    long long value = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
    return value;
}

std::string trim(const std::string& s) {
    std::size_t a = 0, b = s.size();
    while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
    while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
    return s.substr(a, b - a);
}

// One element of a range list: "7", "1-240", "1-240x2", "-5--1".
void appendRangePart(const std::string& spec, const std::string& part, std::vector<int>& out) {
    auto bad = [&](const std::string& why) {
        return usage(fmt::format("--frames {}: '{}': {}", spec, part, why));
    };
    if (part.empty()) throw bad("empty element (expected N, A-B or A-BxSTEP)");
    std::string body = part;
    long long step = 1;
    if (const auto x = body.find('x'); x != std::string::npos) {
        const auto s = parseInteger(std::string_view(body).substr(x + 1));
        if (!s || *s < 1) throw bad("the step after 'x' must be a whole number >= 1");
        step = *s;
        body = body.substr(0, x);
    }
    // The separating '-' is the first one that is not a sign (not at the start, not after '-').
    std::size_t dash = std::string::npos;
    for (std::size_t i = 1; i < body.size(); ++i)
        if (body[i] == '-' && body[i - 1] != '-') {
            dash = i;
            break;
        }
    const auto first = parseInteger(std::string_view(body).substr(0, dash));
    const auto last = dash == std::string::npos ? first : parseInteger(std::string_view(body).substr(dash + 1));
    if (!first || !last) throw bad("expected N, A-B or A-BxSTEP with whole numbers");
    if (dash == std::string::npos && part.find('x') != std::string::npos) throw bad("a step needs a range A-B");
    if (*first < INT_MIN || *first > INT_MAX || *last < INT_MIN || *last > INT_MAX) throw bad("frame number out of range");
    if (*first > *last) throw bad(fmt::format("first frame {} is after last frame {}", *first, *last));
    if ((*last - *first) / step > 10'000'000) throw bad("more than ten million frames");
    for (long long f = *first; f <= *last; f += step) out.push_back(int(f));
}

}  // namespace

std::vector<int> parseFrameRange(const std::string& spec) {
    std::vector<int> all;
    std::size_t start = 0;
    while (true) {
        const auto comma = spec.find(',', start);
        appendRangePart(spec, trim(spec.substr(start, comma - start)), all);
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    std::vector<int> frames;
    std::set<int> seen;
    for (int f : all)
        if (seen.insert(f).second) frames.push_back(f);
    return frames;
}

// ---- patterns ----

namespace {

struct Token {
    std::size_t position = 0, length = 0;
    int width = 0;
};

// Every '#' run and every %d / %0Nd in `text`.
std::vector<Token> findTokens(const std::string& text) {
    std::vector<Token> tokens;
    for (std::size_t i = 0; i < text.size();) {
        if (text[i] == '#') {
            std::size_t j = i;
            while (j < text.size() && text[j] == '#') ++j;
            tokens.push_back({i, j - i, int(j - i)});
            i = j;
        } else if (text[i] == '%') {
            std::size_t j = i + 1;
            int width = 0;
            if (j < text.size() && text[j] == '0') {
                ++j;
                while (j < text.size() && std::isdigit(static_cast<unsigned char>(text[j])))
                    width = width * 10 + (text[j++] - '0');
                if (width == 0 || width > 18) {  // "%0d" or silly widths: not a token
                    ++i;
                    continue;
                }
            }
            if (j < text.size() && text[j] == 'd') {
                tokens.push_back({i, j + 1 - i, width});
                i = j + 1;
            } else {
                ++i;
            }
        } else {
            ++i;
        }
    }
    return tokens;
}

}  // namespace

bool FramePattern::hasToken(const std::string& text) { return !findTokens(text).empty(); }

FramePattern::FramePattern(const std::string& pattern) : text_(pattern) {
    const std::vector<Token> tokens = findTokens(pattern);
    if (tokens.empty())
        throw usage(fmt::format("{}: no frame number in the pattern (use #### or %04d where the frame goes)", pattern));
    if (tokens.size() > 1)
        throw usage(fmt::format("{}: {} frame-number tokens; give exactly one (#### or %04d)", pattern, tokens.size()));
    prefix_ = pattern.substr(0, tokens[0].position);
    suffix_ = pattern.substr(tokens[0].position + tokens[0].length);
    width_ = tokens[0].width;
}

std::string FramePattern::path(int frame) const {
    const std::string digits = fmt::format("{:0{}d}", frame, std::max(width_, 1));
    return prefix_ + digits + suffix_;
}

std::optional<int> FramePattern::match(const std::string& candidate) const {
    if (candidate.size() <= prefix_.size() + suffix_.size() || !candidate.starts_with(prefix_) ||
        !candidate.ends_with(suffix_))
        return std::nullopt;
    const std::string middle = candidate.substr(prefix_.size(), candidate.size() - prefix_.size() - suffix_.size());
    const auto value = parseInteger(middle);
    if (!value || *value < INT_MIN || *value > INT_MAX || path(int(*value)) != candidate) return std::nullopt;
    return int(*value);
}

std::vector<int> discoverFrames(const FramePattern& input) {
    const fs::path pattern(input.text());
    const std::string name = pattern.filename().string();
    if (!FramePattern::hasToken(name))
        throw usage(fmt::format("{}: finding frames needs the frame number in the file name; give --frames", input.text()));
    const fs::path folder = pattern.parent_path().empty() ? fs::path(".") : pattern.parent_path();
    const FramePattern names(name);
    std::vector<int> frames;
    std::error_code ec;
    for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec))
        if (auto frame = names.match(it->path().filename().string())) frames.push_back(*frame);
    if (ec) throw inputError(fmt::format("{}: cannot list {}: {}", input.text(), folder.string(), ec.message()));
    if (frames.empty()) throw inputError(fmt::format("{}: no file matches the pattern; give --frames", input.text()));
    std::sort(frames.begin(), frames.end());
    return frames;
}

// ---- shards ----

const char* shardModeName(ShardMode mode) { return mode == ShardMode::Interleaved ? "interleaved" : "contiguous"; }

Shard parseShard(const std::string& spec) {
    const auto slash = spec.find('/');
    const auto index = slash == std::string::npos ? std::nullopt : parseInteger(std::string_view(spec).substr(0, slash));
    const auto count = slash == std::string::npos ? std::nullopt : parseInteger(std::string_view(spec).substr(slash + 1));
    if (!index || !count) throw usage(fmt::format("--shard {}: expected I/N, e.g. 3/8 (the third of eight)", spec));
    if (*count < 1 || *count > 1'000'000) throw usage(fmt::format("--shard {}: N must be 1 or more", spec));
    if (*index < 1 || *index > *count)
        throw usage(fmt::format("--shard {}: I must be between 1 and {} (shards are numbered from 1)", spec, *count));
    return {int(*index), int(*count)};
}

std::optional<Shard> shardFromSlurmEnvironment(const EnvironmentLookup& getenv) {
    const char* id = getenv("SLURM_ARRAY_TASK_ID");
    if (!id) return std::nullopt;
    const char* count = getenv("SLURM_ARRAY_TASK_COUNT");
    const char* min = getenv("SLURM_ARRAY_TASK_MIN");
    const char* step = getenv("SLURM_ARRAY_TASK_STEP");
    auto number = [](const char* name, const char* text) {
        const auto v = parseInteger(text ? std::string_view(text) : std::string_view());
        if (!v) throw usage(fmt::format("{}={}: not a whole number (give --shard I/N)", name, text ? text : ""));
        return *v;
    };
    if (!count)
        throw usage("SLURM_ARRAY_TASK_ID is set but SLURM_ARRAY_TASK_COUNT is not (Slurm older than 17.11?): "
                    "give --shard I/N");
    const long long task = number("SLURM_ARRAY_TASK_ID", id);
    const long long n = number("SLURM_ARRAY_TASK_COUNT", count);
    const long long first = min ? number("SLURM_ARRAY_TASK_MIN", min) : 0;
    const long long stride = step ? number("SLURM_ARRAY_TASK_STEP", step) : 1;
    const std::string seen = fmt::format("SLURM_ARRAY_TASK_ID={} MIN={} STEP={} COUNT={}", task, first, stride, n);
    if (stride < 1 || n < 1 || (task - first) % stride != 0)
        throw usage(fmt::format("{}: not an evenly spaced array; give --shard I/N", seen));
    const long long index = (task - first) / stride + 1;
    if (index < 1 || index > n)
        throw usage(fmt::format("{}: task is shard {} of {}; arrays with gaps (1,3,7) need --shard I/N", seen, index, n));
    return Shard{int(index), int(n)};
}

std::vector<int> shardFrames(const std::vector<int>& frames, const Shard& shard, ShardMode mode) {
    std::vector<int> out;
    const std::size_t n = frames.size(), count = std::size_t(shard.count), i = std::size_t(shard.index - 1);
    if (mode == ShardMode::Interleaved) {
        for (std::size_t k = i; k < n; k += count) out.push_back(frames[k]);
    } else {
        // Runs of n / count frames, the first n % count of them one longer.
        const std::size_t base = n / count, extra = n % count;
        const std::size_t begin = i * base + std::min(i, extra);
        const std::size_t length = base + (i < extra ? 1 : 0);
        out.assign(frames.begin() + std::ptrdiff_t(begin), frames.begin() + std::ptrdiff_t(begin + length));
    }
    return out;
}

}  // namespace decalcomp
