// The memory cap for one input (docs/cli.md, "Limits").
#include "decalcomp/memory_limit.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cctype>
#include <cstdlib>

#include "decalcomp/error.hpp"

namespace decalcomp {

namespace {

constexpr const char* kVariable = "DECALCOMP_MAX_MEMORY";

std::uint64_t physicalMemory() {
    const long pages = ::sysconf(_SC_PHYS_PAGES);
    const long page_size = ::sysconf(_SC_PAGESIZE);
    if (pages <= 0 || page_size <= 0) return std::uint64_t(16) << 30;  // unknown: a modest machine
    return std::uint64_t(pages) * std::uint64_t(page_size);
}

}  // namespace

std::optional<std::uint64_t> checkedProduct(std::uint64_t a, std::uint64_t b) {
    std::uint64_t product = 0;
    if (__builtin_mul_overflow(a, b, &product)) return std::nullopt;
    return product;
}

std::optional<std::uint64_t> parseByteSize(const std::string& text) {
    std::size_t digits = 0;
    while (digits < text.size() && std::isdigit(static_cast<unsigned char>(text[digits]))) ++digits;
    if (digits == 0 || digits > 19) return std::nullopt;
    std::uint64_t multiple = 1;
    const std::string suffix = text.substr(digits);
    if (suffix == "K" || suffix == "k") multiple = std::uint64_t(1) << 10;
    else if (suffix == "M" || suffix == "m") multiple = std::uint64_t(1) << 20;
    else if (suffix == "G" || suffix == "g") multiple = std::uint64_t(1) << 30;
    else if (suffix == "T" || suffix == "t") multiple = std::uint64_t(1) << 40;
    else if (!suffix.empty()) return std::nullopt;
    const auto value = checkedProduct(std::stoull(text.substr(0, digits)), multiple);
    if (!value || *value == 0) return std::nullopt;
    return value;
}

std::uint64_t inputMemoryLimit() {
    const char* setting = std::getenv(kVariable);
    if (!setting || !*setting) return physicalMemory();
    const auto limit = parseByteSize(setting);
    if (!limit)
        throw Error(ErrorKind::Usage, fmt::format("{}={}: not a size; give bytes, or a number with K, M, G or T, "
                                                  "e.g. {}=8G",
                                                  kVariable, setting, kVariable));
    return *limit;
}

std::string readableBytes(std::uint64_t bytes) {
    constexpr const char* kUnits[] = {"KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
    if (bytes < 1024) return fmt::format("{} bytes", bytes);
    double value = double(bytes) / 1024.0;
    int unit = 0;
    while (value >= 1024.0 && unit < 5) value /= 1024.0, ++unit;
    return fmt::format("{:.3g} {}", value, kUnits[unit]);
}

void requireWithinMemoryLimit(std::uint64_t bytes, const std::string& file, const std::string& what) {
    const std::uint64_t limit = inputMemoryLimit();
    if (bytes > limit)
        throw inputError(fmt::format("{}: {}: decodes to {}, more than the memory limit of {} (raise it with "
                                     "{}, e.g. {}=64G, if the file is genuine)",
                                     file, what, readableBytes(bytes), readableBytes(limit), kVariable, kVariable));
}

}  // namespace decalcomp
