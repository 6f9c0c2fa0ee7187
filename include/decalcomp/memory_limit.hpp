#pragma once
// How much memory one input may decode to, checked before anything is allocated for it.
#include <cstdint>
#include <optional>
#include <string>

namespace decalcomp {

// DECALCOMP_MAX_MEMORY (bytes; suffix K, M, G or T for binary multiples), else the machine's
// physical memory. Throws Error(Usage) naming the variable when it is not a size.
std::uint64_t inputMemoryLimit();

// Parses "512M", "8G", "1073741824"; nullopt when it is not a size.
std::optional<std::uint64_t> parseByteSize(const std::string& text);

// "1.5 GiB", "300 MiB", "12 KiB", "7 bytes".
std::string readableBytes(std::uint64_t bytes);

// a * b, or nullopt when it does not fit in 64 bits.
std::optional<std::uint64_t> checkedProduct(std::uint64_t a, std::uint64_t b);

// Throws Error(Input) "FILE: WHAT: decodes to N, more than the memory limit M (DECALCOMP_MAX_MEMORY)".
void requireWithinMemoryLimit(std::uint64_t bytes, const std::string& file, const std::string& what);

}  // namespace decalcomp
