// CLI11's parse errors, reworded into decalcomp's one-line form with what to do next.
#include "usage_message.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <vector>

#include "decalcomp/edit_distance.hpp"

namespace decalcomp::cli {

namespace {

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
