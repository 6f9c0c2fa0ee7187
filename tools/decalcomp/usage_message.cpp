// CLI11's parse errors, reworded into decalcomp's one-line form with what to do next.
#include "usage_message.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <numeric>
#include <vector>

namespace decalcomp::cli {

namespace {

// Levenshtein distance: the number of single-character edits from a to b.
std::size_t editDistance(const std::string& a, const std::string& b) {
    std::vector<std::size_t> row(b.size() + 1);
    std::iota(row.begin(), row.end(), std::size_t{0});
    for (std::size_t i = 1; i <= a.size(); ++i) {
        std::size_t diagonal = row[0];
        row[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t above = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
            diagonal = above;
        }
    }
    return row[b.size()];
}

std::vector<std::string> subcommandNames(const CLI::App& app) {
    std::vector<std::string> names;
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
        names.push_back(sub->get_name());
    return names;
}

std::string joined(const std::vector<std::string>& names) {
    std::string text;
    for (const std::string& name : names) text += (text.empty() ? "" : ", ") + name;
    return text;
}

}  // namespace

std::optional<std::string> nearestName(const std::string& word, const std::vector<std::string>& names) {
    std::optional<std::string> best;
    std::size_t best_distance = 0;
    for (const std::string& name : names) {
        const std::size_t distance = editDistance(word, name);
        if (!best || distance < best_distance) best = name, best_distance = distance;
    }
    // More edits than half the word is a different word, not a typo.
    if (best && best_distance * 2 > std::max(word.size(), std::size_t{2})) return std::nullopt;
    return best;
}

std::string usageMessage(const CLI::App& app, const CLI::ParseError& error, int argc, char** argv) {
    const std::vector<std::string> commands = subcommandNames(app);
    const std::string first = argc > 1 ? argv[1] : "";
    const bool is_command = std::find(commands.begin(), commands.end(), first) != commands.end();
    if (!is_command && (first.empty() || first[0] != '-')) {
        if (first.empty())
            return fmt::format("no command given: expected one of {}; 'decalcomp --help' lists them", joined(commands));
        if (const auto nearest = nearestName(first, commands))
            return fmt::format("{}: not a command; did you mean '{}'? (commands: {})", first, *nearest,
                               joined(commands));
        return fmt::format("{}: not a command; expected one of {}", first, joined(commands));
    }
    const std::string help = is_command ? fmt::format("decalcomp {} --help", first) : "decalcomp --help";
    return fmt::format("{}{}; '{}' lists the options", is_command ? first + ": " : "", error.what(), help);
}

}  // namespace decalcomp::cli
