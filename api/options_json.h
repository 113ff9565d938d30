#pragma once
// Remesh options as JSON: the `options` part of an upload, the query parameters of
// POST /v1/jobs, and the normalized options stored with a job.
//
//   {"edge_length": number > 0 | null, "vertices": integer > 0 | null, "rosy": 4 | 6,
//    "sizing": "uniform" | "curvature", "placement": "balanced" | "on_surface",
//    "feature_angle": number in [0, 180], "d_sing": number >= 0 | null}
//
// null (or absent) means the pipeline's default (RemeshOptions documents them).

#include <array>
#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

#include "api/option_names.h"
#include "core/pipeline/pipeline.h"

namespace hexcover::api {

/// A word an enumerated option takes (in JSON and on the command line alike).
template <typename E>
struct OptionWord {
  std::string_view word;
  E value;
};

inline constexpr std::array<OptionWord<Sizing>, 2> kSizingWords{
    {{"uniform", Sizing::Uniform}, {"curvature", Sizing::Curvature}}};
inline constexpr std::array<OptionWord<VertexPlacement>, 2> kPlacementWords{
    {{"balanced", VertexPlacement::Balanced}, {"on_surface", VertexPlacement::OnSurface}}};

/// The value of `word`, or nullopt when the option does not take it.
template <typename E, std::size_t K>
std::optional<E> valueOfWord(const std::array<OptionWord<E>, K>& words, std::string_view word) {
  for (const auto& w : words)
    if (w.word == word) return w.value;
  return std::nullopt;
}

/// The word of `value`.
template <typename E, std::size_t K>
std::string_view wordOf(const std::array<OptionWord<E>, K>& words, E value) {
  for (const auto& w : words)
    if (w.value == value) return w.word;
  return {};
}

/// "a or b" (each word between `quote`s) for messages that list an option's words.
template <typename E, std::size_t K>
std::string wordList(const std::array<OptionWord<E>, K>& words, std::string_view quote = "") {
  std::string list;
  for (std::size_t i = 0; i < K; ++i) {
    if (i > 0) list += i + 1 == K ? " or " : ", ";
    list.append(quote).append(words[i].word).append(quote);
  }
  return list;
}

/// Reads options from a JSON object, checking names and types (layer 2 of validation: syntax is
/// nlohmann's, ranges and consistency are RemeshOptions::validate's). Throws
/// Error(InvalidOption) naming the option: unknown name, wrong type, or a value that no range
/// could accept (e.g. a fractional vertex count).
RemeshOptions remeshOptionsFromJson(const nlohmann::json& options);

/// Every option, defaults included (the normalized form stored with a job).
nlohmann::json toJson(const RemeshOptions& options);

}  // namespace hexcover::api
