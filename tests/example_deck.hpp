// An example's deck with other .geo constants (and optionally coarser increments), written to
// a temporary folder beside a copy of its .geo files: the default suite runs the examples'
// decks on coarser meshes than they ship with.
#pragma once
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <unistd.h>

namespace signorini::test {

struct ExampleDeck {
  std::filesystem::path dir;   // the temporary folder (remove it when done)
  std::filesystem::path deck;  // the deck in it
};

// `parameters`: the .geo constants, e.g. "hc: 0.25, order: 1" (empty: as shipped); increments
// whose initial size is below `min_increment` become {initial: min_increment, max: the same}.
inline ExampleDeck example_deck_with(const std::string& example, const std::string& parameters,
                                     double min_increment = 0) {
  namespace fs = std::filesystem;
  const fs::path src = fs::path(SIGNORINI_SOURCE_DIR) / "examples" / example;
  ExampleDeck out;
  out.dir = fs::temp_directory_path() / ("signorini_" + example + "_" + std::to_string(::getpid()));
  fs::create_directories(out.dir);
  for (const auto& e : fs::directory_iterator(src))
    if (e.path().extension() == ".geo") fs::copy_file(e.path(), out.dir / e.path().filename(), fs::copy_options::overwrite_existing);
  std::ifstream in(src / (example + ".yaml"));
  std::string deck((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string geo = "file: " + example + ".geo}";
  EXPECT_NE(deck.find(geo), std::string::npos) << "the deck's mesh entry is not {file: " << example << ".geo}";
  if (!parameters.empty() && deck.find(geo) != std::string::npos)
    deck.replace(deck.find(geo), geo.size(), "file: " + example + ".geo, parameters: {" + parameters + "}}");
  for (size_t at = 0; min_increment > 0 && (at = deck.find("increments: {initial: ", at)) != std::string::npos; ++at) {
    const size_t end = deck.find('}', at);
    if (std::stod(deck.substr(at + 22)) < min_increment)
      deck.replace(at, end - at + 1,
                   "increments: {initial: " + std::to_string(min_increment) + ", max: " + std::to_string(min_increment) + "}");
  }
  out.deck = out.dir / (example + ".yaml");
  std::ofstream(out.deck) << deck;
  return out;
}

// Replaces the first `from` in the example deck's text by `to` (a pair's entry, a line); false,
// and the deck unchanged, when `from` is not in it.
inline bool replace_in_deck(const ExampleDeck& ex, const std::string& from, const std::string& to) {
  std::ifstream in(ex.deck);
  std::string deck((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  const size_t at = deck.find(from);
  if (at == std::string::npos) return false;
  deck.replace(at, from.size(), to);
  std::ofstream(ex.deck) << deck;
  return true;
}

}  // namespace signorini::test
