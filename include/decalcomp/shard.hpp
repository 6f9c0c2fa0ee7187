#pragma once
// Shards: one machine's part of a frame range, explicit or from a Slurm job array (docs/farm.md).
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace decalcomp {

enum class ShardMode { Interleaved, Contiguous };
const char* shardModeName(ShardMode mode);

struct Shard {
    int index = 1;  // 1-based: 1..count (as `split -n l/K/N`)
    int count = 1;
};

// "I/N" with 1 <= I <= N. Throws Error(Usage).
Shard parseShard(const std::string& spec);

// From a Slurm job array: index = (SLURM_ARRAY_TASK_ID - SLURM_ARRAY_TASK_MIN) / step + 1 (step from
// SLURM_ARRAY_TASK_STEP, default 1), count = SLURM_ARRAY_TASK_COUNT. nullopt outside an array job;
// Error(Usage) when the variables are inconsistent (non-numeric, index out of range).
using EnvironmentLookup = std::function<const char*(const char*)>;
std::optional<Shard> shardFromSlurmEnvironment(const EnvironmentLookup& getenv);

// Interleaved: positions index-1, index-1+count, ...; contiguous: the index-th of `count` runs of
// (nearly) equal length, earlier runs one longer when the sizes do not divide.
std::vector<int> shardFrames(const std::vector<int>& frames, const Shard& shard, ShardMode mode);

}  // namespace decalcomp
