// Flags that several verbs share, each with its help line defined once and parsed in one place:
// the simplification options (build, simplify), a level of detail (simplify, extract) and the
// surface sampling (hausdorff, eval). A verb lists the FlagSpecs in its VerbSpec, in the order
// its help shows them, and calls the parse_ function after parse_verb_args(). A flag a verb
// does not list is never present, so each parse_ function reads only what the verb offers.
#pragma once

#include <cstdint>
#include <optional>

#include "args.h"
#include "dynpm/eval.h"
#include "dynpm/simplify.h"

namespace dynpm::cli {

// ---- Simplification (build, simplify): how collapses are rated and limited.
inline const FlagSpec kKeyStepsFlag{"--key-steps", "", true, "RULE",
                                    "steps that rate collapses: all (default), paper, auto:K, "
                                    "0,12,24"};
inline const FlagSpec kBoundaryWeightFlag{"--boundary-weight", "", true, "W",
                                          "weight of boundary/feature constraint planes (1)"};
inline const FlagSpec kFieldFlag{"--field", "", true, "NAME[:W]",
                                 "a result field in the cost, at weight W (repeatable; naming "
                                 "fields leaves the others out)"};
inline const FlagSpec kFieldWeightFlag{"--field-weight", "", true, "W",
                                       "weight of every field in the cost: a change of the "
                                       "field's whole range multiplies the geometric error by "
                                       "1 + W (3; with --field-cost …,add it costs W diagonals; 0: "
                                       "geometry only)"};
inline const FlagSpec kFieldCostFlag{"--field-cost", "", true, "FORM[,COMBINE]",
                                     "what the field term measures: spread (default), "
                                     "attributes, quadric; and how it meets the geometry: scale "
                                     "(default), add"};
inline const FlagSpec kRegularizeFlag{"--regularize", "", true, "W",
                                      "shape term keeping flat regions well shaped (default 0: "
                                      "off; 0.001 measured)"};
inline const FlagSpec kRoundsFlag{"--rounds", "", true, "F",
                                  "collapse in rounds of independent collapses, each at most "
                                  "F of the vertices (0: off, the default; docs/selective.md)"};
inline const FlagSpec kIgnorePartsFlag{"--ignore-parts", "", false, "",
                                       "let collapses cross part boundaries"};

// --key-steps (default all) into `key_steps`; --boundary-weight, --field, --field-weight,
// --field-cost,
// --regularize, --rounds, --ignore-parts and --threads (kThreadsFlag, where the verb lists it) into
// `options`. The error is the usage message, without the
// verb.
Status parse_simplify_flags(const Args& args, SimplifyOptions& options, KeyStepRule& key_steps);
// The fields --field names exist in the input (cost_fields()); the error is the usage message.
Status check_cost_fields(const SimplifyOptions& options, const FrameSource& frames);

// ---- How exactly a build stores positions and fields (build, and batch that passes them on).
inline const FlagSpec kLosslessFlag{"--lossless", "", false, "",
                                    "store positions and fields bit-exactly (larger file)"};
inline const FlagSpec kPositionErrorFlag{"--position-error", "", true, "E",
                                         "largest position error, in diagonals (3.8e-6)"};
inline const FlagSpec kFieldBoundFlag{"--field-bound", "", true, "F",
                                      "largest field value error, in % of its range (0.1)"};
inline const FlagSpec kNoMemoryCheckFlag{
    "--no-memory-check", "", false, "",
    "build even when the memory estimate exceeds the memory available"};
struct QuantizationFlags {
  bool lossless = false;
  std::optional<double> position_error;  // in diagonals
  std::optional<double> field_bound;     // a fraction of each field's range
};
// The error is the usage message, without the verb.
Result<QuantizationFlags> parse_quantization_flags(const Args& args);

// ---- A level of detail (simplify's targets, extract's resolution).
struct LevelFlags {
  std::optional<double> ratio;        // --ratio, a fraction of the vertices in (0, 1]
  std::optional<uint64_t> vertices;   // --vertices, ≥ 1
  std::optional<uint64_t> faces;      // --faces, ≥ 1
  std::optional<double> max_error;    // --max-error, as given (E, or E of "E%")
  bool max_error_in_percent = false;  // "E%": max_error is in % of the diagonal
};
// The error is the usage message, without the verb.
Result<LevelFlags> parse_level_flags(const Args& args);

// ---- A time step (extract): a number, fractional between two steps, or the model's last.
struct StepChoice {
  double value = 0;   // the step, when not `last`
  bool last = false;  // "last": known once the model's step count is read
  // What a reader decodes: the steps up to this one (every step for "last").
  std::optional<size_t> last_step_to_read() const;
  // The step in a model of `steps` steps; the error is the usage message, without the verb.
  Result<double> in_model(size_t steps, const std::string& path) const;
  std::string text;  // as given, for messages
};
// --step T|last; nothing when it is not given. The error is the usage message.
Result<std::optional<StepChoice>> parse_step_flag(const Args& args);

// ---- Surface sampling (hausdorff, eval): HausdorffOptions.
inline const FlagSpec kSamplesFlag{"--samples", "", true, "N",
                                   "area samples on each surface (default 10 per face of the "
                                   "larger)"};
inline const FlagSpec kSamplesPerFaceFlag{"--samples-per-face", "", true, "K",
                                          "area samples per face of the larger mesh (default 10)"};
inline const FlagSpec kSeedFlag{"--seed", "", true, "S", "seed of the sampling (default 1)"};
inline const FlagSpec kThreadsFlag{"--threads", "", true, "T",
                                   "worker threads (default: all cores)"};

// --samples, --seed, --threads, --samples-per-face into `options`. The error is the usage
// message, without the verb.
Status parse_sampling_flags(const Args& args, HausdorffOptions& options);

}  // namespace dynpm::cli
