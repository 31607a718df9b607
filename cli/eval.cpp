// dynpm eval: how far a progressive mesh is from the animation it was built from, at several
// resolutions and time steps (the paper's Table 2): two-sided Metro-style Hausdorff distance in
// % of the bounding-box diagonal over all steps (as 'dynpm hausdorff' for sequences).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "args.h"
#include "commands.h"
#include "dynpm/eval.h"
#include "dynpm/lod.h"
#include "json.h"

namespace dynpm::cli {
namespace {

const VerbSpec kSpec{
    "eval",
    "dynpm eval ORIGINAL... --dpm MODEL.dpm --ratios 1,2,4,11 [--steps 0,12,24]\n"
    "                  [--samples N] [--seed S] [--threads T] [--json OUT.json] [--plot OUT.svg]",
    "Measures a progressive mesh against the animation it was built from, as the paper's\n"
    "Table 2 does: for each resolution (--ratios, in % of the full vertex count) and each\n"
    "chosen time step (--steps, default the first, middle and last), the two-sided Hausdorff\n"
    "distance (Metro-style, as 'dynpm hausdorff') between the original at step t and the\n"
    "progressive mesh at step t, in % of the bounding-box diagonal over all steps.\n"
    "The column 'max' is the largest over every step of the animation (--max-over chosen: over\n"
    "the chosen steps only). ORIGINAL is a mesh file or a quoted glob of step files.",
    {{"--dpm", "", true, "MODEL.dpm", "the progressive mesh (from dynpm build)"},
     {"--ratios", "", true, "R,R,…", "resolutions in % of the full vertex count, each in (0, 100]"},
     {"--steps", "", true, "T,T,…", "time steps of the table (default: first, middle, last)"},
     {"--max-over", "", true, "all|chosen", "steps of the 'max' column (default all)"},
     {"--samples", "", true, "N",
      "area samples on each surface (default 10 per face of the larger)"},
     {"--seed", "", true, "S", "seed of the sampling (default 1)"},
     {"--threads", "", true, "T", "worker threads (default: all cores)"},
     {"--json", "", true, "OUT.json", "also write the results as JSON"},
     {"--plot", "", true, "OUT.svg", "also write an SVG plot of error against % of vertices"},
     {"--split-polygons", "", false, "", "fan-split faces with more than 4 corners"}}};

int fail_usage(const std::string& message) {
  std::cerr << "dynpm eval: " << message << "\n";
  return kExitUsage;
}

int fail(const std::string& message) {
  std::cerr << "dynpm eval: " << message << "\n";
  return kExitFailure;
}

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) items.push_back(item);
  if (!text.empty() && text.back() == ',') items.emplace_back();
  return items;
}

// One measurement: original at step t against the model at one resolution.
struct Cell {
  double hausdorff_pct = 0, mean_pct = 0, rms_pct = 0, diagonal = 0;
};

struct Row {
  double ratio = 0;  // requested, % of the full vertex count
  uint32_t vertices = 0, faces = 0, level = 0;
  double error = 0;  // the level's simplification error, absolute
  Topology topology;
  std::vector<Cell> chosen;  // per chosen step
  Cell max;                  // each value's max over the measured steps
  size_t max_step = 0;       // where the Hausdorff max was found
};

std::string format_number(double v, int digits = 4) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*g", digits, v);
  return text;
}

std::string xml_escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '&')
      out += "&amp;";
    else if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '"')
      out += "&quot;";
    else
      out += c;
  }
  return out;
}

// A "nice" tick spacing (1, 2 or 5 × 10^k) giving about `count` intervals over [0, range].
double nice_step(double range, int count) {
  if (!(range > 0)) return 1;
  const double raw = range / count;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (raw <= m * power) return m * power;
  return 10 * power;
}

// Error (% diagonal, y, linear) against % of vertices (x, log scale): one polyline per chosen
// step and one for the max over steps.
std::string svg_plot(const std::vector<Row>& rows, const std::vector<size_t>& steps,
                     const std::string& max_label, uint32_t full_vertices,
                     const std::string& title) {
  const double width = 760, height = 480, left = 80, right = 200, top = 50, bottom = 60;
  const double plot_w = width - left - right, plot_h = height - top - bottom;
  auto x_of = [&](const Row& r) { return 100.0 * r.vertices / full_vertices; };
  double x_lo = 100, x_hi = 0, y_hi = 0;
  for (const Row& r : rows) {
    x_lo = std::min(x_lo, x_of(r));
    x_hi = std::max(x_hi, x_of(r));
    y_hi = std::max(y_hi, r.max.hausdorff_pct);
    for (const Cell& c : r.chosen) y_hi = std::max(y_hi, c.hausdorff_pct);
  }
  // Whole decades around the data (at least one decade wide).
  double lx0 = std::floor(std::log10(std::max(x_lo, 1e-6)) + 0.02);  // 0.997 % → 1
  double lx1 = std::ceil(std::log10(std::max(x_hi, 1e-6)) - 0.02);
  if (lx1 <= lx0) lx1 = lx0 + 1;
  const double y_step = nice_step(y_hi > 0 ? y_hi : 1, 5);
  const double y_top = std::max(y_step, std::ceil(y_hi / y_step) * y_step);
  auto px = [&](double x) {
    return left + (std::log10(std::max(x, 1e-6)) - lx0) / (lx1 - lx0) * plot_w;
  };
  auto py = [&](double y) { return top + plot_h - y / y_top * plot_h; };

  std::string s;
  char buf[512];
  auto add = [&](const char* format, auto... values) {
    std::snprintf(buf, sizeof buf, format, values...);
    s += buf;
  };
  add("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%g\" height=\"%g\" viewBox=\"0 0 %g "
      "%g\" font-family=\"sans-serif\" font-size=\"12\">\n",
      width, height, width, height);
  add("<rect width=\"%g\" height=\"%g\" fill=\"white\"/>\n", width, height);
  s += "<text x=\"" + format_number(left + plot_w / 2) +
       "\" y=\"24\" text-anchor=\"middle\" font-size=\"14\">" + xml_escape(title) + "</text>\n";
  // Grid, ticks and labels.
  for (double d = lx0; d <= lx1 + 1e-9; ++d)
    for (int m : {1, 2, 5}) {
      const double x = m * std::pow(10.0, d);
      if (std::log10(x) > lx1 + 1e-9) break;
      const double X = px(x);
      add("<line x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" stroke=\"%s\"/>\n", X, top, X,
          top + plot_h, m == 1 ? "#ccc" : "#eee");
      add("<text x=\"%.2f\" y=\"%.2f\" text-anchor=\"middle\">%s</text>\n", X, top + plot_h + 18,
          format_number(x).c_str());
    }
  for (double y = 0; y <= y_top + y_step * 1e-6; y += y_step) {
    const double Y = py(y);
    add("<line x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" stroke=\"#ddd\"/>\n", left, Y,
        left + plot_w, Y);
    add("<text x=\"%.2f\" y=\"%.2f\" text-anchor=\"end\">%s</text>\n", left - 6, Y + 4,
        format_number(y).c_str());
  }
  add("<rect x=\"%g\" y=\"%g\" width=\"%g\" height=\"%g\" fill=\"none\" stroke=\"black\"/>\n", left,
      top, plot_w, plot_h);
  add("<text x=\"%.2f\" y=\"%.2f\" text-anchor=\"middle\">vertices (%% of %u, log scale)</text>\n",
      left + plot_w / 2, height - 16, full_vertices);
  add("<text transform=\"translate(%g %.2f) rotate(-90)\" text-anchor=\"middle\">two-sided "
      "Hausdorff distance (%% of the diagonal)</text>\n",
      22.0, top + plot_h / 2);

  // Series: the chosen steps, then the max (black, dashed).
  static const char* const kColours[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                                         "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};
  std::vector<size_t> order(rows.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return x_of(rows[a]) < x_of(rows[b]); });
  for (size_t k = 0; k <= steps.size(); ++k) {
    const bool is_max = k == steps.size();
    const char* colour = is_max ? "black" : kColours[k % 10];
    std::string points;
    for (size_t i : order) {
      const double y = is_max ? rows[i].max.hausdorff_pct : rows[i].chosen[k].hausdorff_pct;
      points += format_number(px(x_of(rows[i])), 6) + "," + format_number(py(y), 6) + " ";
    }
    s += std::string("<polyline fill=\"none\" stroke=\"") + colour + "\" stroke-width=\"2\"" +
         (is_max ? " stroke-dasharray=\"6 4\"" : "") + " points=\"" + points + "\"/>\n";
    for (size_t i : order) {
      const double y = is_max ? rows[i].max.hausdorff_pct : rows[i].chosen[k].hausdorff_pct;
      add("<circle cx=\"%.2f\" cy=\"%.2f\" r=\"3\" fill=\"%s\"/>\n", px(x_of(rows[i])), py(y),
          colour);
    }
    // Legend entry.
    const double ly = top + 10 + 20 * double(k), lx = left + plot_w + 16;
    add("<line x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" stroke=\"%s\" stroke-width=\"2\"%s/>"
        "\n",
        lx, ly, lx + 24, ly, colour, is_max ? " stroke-dasharray=\"6 4\"" : "");
    const std::string label = is_max ? max_label : "step " + std::to_string(steps[k]);
    add("<text x=\"%.2f\" y=\"%.2f\">%s</text>\n", lx + 30, ly + 4, xml_escape(label).c_str());
  }
  s += "</svg>\n";
  return s;
}

}  // namespace

int run_eval(std::span<char* const> arguments) {
  Args args;
  if (auto exit_code = parse_verb_args(arguments, kSpec, args)) return *exit_code;
  const auto dpm_path = args.value("--dpm");
  const auto ratios_text = args.value("--ratios");
  if (args.positional.empty() || !dpm_path || !ratios_text) {
    std::cerr << "dynpm eval: needs the ORIGINAL animation, --dpm MODEL.dpm and --ratios\n\n"
              << help_text(kSpec);
    return kExitUsage;
  }

  // Ratios: % of the full vertex count, in (0, 100]; sorted, duplicates dropped.
  std::vector<double> ratios;
  for (const std::string& item : split_list(*ratios_text)) {
    auto r = parse_number("--ratios", item, {0, 100, true});
    if (!r) return fail_usage(r.message() + " (percentages separated by commas)");
    ratios.push_back(*r);
  }
  std::sort(ratios.begin(), ratios.end());
  ratios.erase(std::unique(ratios.begin(), ratios.end()), ratios.end());

  std::vector<uint64_t> step_values;
  if (auto text = args.value("--steps"))
    for (const std::string& item : split_list(*text)) {
      auto t = parse_whole("--steps", item, 0, 0xffffffffu);
      if (!t) return fail_usage(t.message() + " (step numbers separated by commas)");
      step_values.push_back(*t);
    }
  bool max_over_all = true;
  if (auto text = args.value("--max-over")) {
    if (*text != "all" && *text != "chosen") return fail_usage("--max-over is 'all' or 'chosen'");
    max_over_all = *text == "all";
  }
  HausdorffOptions h;
  struct NumberFlag {
    const char* name;
    uint64_t* whole;
    uint64_t max;
  };
  uint64_t threads = 0;
  for (const NumberFlag& flag : {NumberFlag{"--samples", &h.face_samples, kMaxSamples},
                                 NumberFlag{"--seed", &h.seed, UINT64_MAX},
                                 NumberFlag{"--threads", &threads, kMaxThreads}}) {
    const auto text = args.value(flag.name);
    if (!text) continue;
    auto r = parse_whole(flag.name, *text, 0, flag.max);
    if (!r) return fail_usage(r.message());
    *flag.whole = *r;
  }
  h.threads = static_cast<unsigned>(threads);
  const auto json_path = args.value("--json");
  const auto plot_path = args.value("--plot");

  // The original animation and the model.
  auto files = expand_inputs(args.positional);
  if (!files) return fail(files.message());
  auto stream = open_inputs(*files, args.has("--split-polygons"));
  if (!stream) return fail(stream.message());
  const Topology& original = stream->topology;
  const FrameSource& frames = *stream->frames;
  const size_t steps = frames.step_count();
  if (steps == 0) return fail(files->front() + ": no time steps");

  auto mesh = read_dpm(*dpm_path);
  if (!mesh) return fail(mesh.message());
  if (mesh->full_vertex_count != original.vertex_count ||
      mesh->full_face_count != original.faces.size())
    return fail(*dpm_path + " was built from another mesh: it has " +
                std::to_string(mesh->full_vertex_count) + " vertices and " +
                std::to_string(mesh->full_face_count) + " faces, the original " +
                std::to_string(original.vertex_count) + " vertices and " +
                std::to_string(original.faces.size()) + " faces");
  // One reference length for every step, as 'dynpm hausdorff' uses for step sequences: the
  // bounding-box diagonal over all steps (the model's box is the original's, within the
  // position bound), so that the columns compare like with like.
  if (h.reference_diagonal == 0) h.reference_diagonal = mesh->diagonal();
  if (mesh->step_count() != steps)
    return fail(*dpm_path + " was built from another animation: it has " +
                std::to_string(mesh->step_count()) + " time steps, the original " +
                std::to_string(steps));
  if (!mesh->complete)
    std::cerr << "dynpm eval: note: " << *dpm_path << " is a prefix of a file; it holds "
              << mesh->split_count() << " of " << mesh->full_split_count
              << " splits, so the finest level is " << mesh->vertex_count() << " vertices\n";

  // The table's steps: as given, or the first, middle and last.
  std::vector<size_t> chosen;
  for (uint64_t t : step_values) {
    if (t > steps - 1)
      return fail_usage("--steps needs step numbers in [0, " + std::to_string(steps - 1) +
                        "] (the animation has " + std::to_string(steps) + " steps), got " +
                        std::to_string(t));
    chosen.push_back(static_cast<size_t>(t));
  }
  if (step_values.empty()) chosen = {0, (steps - 1) / 2, steps - 1};
  std::sort(chosen.begin(), chosen.end());
  chosen.erase(std::unique(chosen.begin(), chosen.end()), chosen.end());

  // One row per ratio: the level's faces, kept as a Topology. Positions need no level: vertex
  // v has the same position at every level where it exists, so the finest level's positions
  // serve every row (a prefix of them).
  Navigator nav(*mesh);
  std::vector<Row> rows;
  for (double ratio : ratios) {
    const double wanted = std::round(ratio / 100.0 * mesh->full_vertex_count);
    nav.set_vertex_count(static_cast<uint32_t>(std::max(1.0, wanted)));
    Row row;
    row.ratio = ratio;
    row.vertices = nav.vertex_count();
    row.faces = nav.face_count();
    row.level = nav.level();
    row.error = nav.error();
    row.topology = nav.topology();
    row.chosen.resize(chosen.size());
    rows.push_back(std::move(row));
  }
  nav.set_level(mesh->split_count());

  std::vector<size_t> measured;  // the steps of the max column
  if (max_over_all)
    for (size_t t = 0; t < steps; ++t) measured.push_back(t);
  else
    measured = chosen;
  std::vector<float> original_xyz(size_t{original.vertex_count} * 3);
  std::vector<float> model_xyz(size_t{nav.vertex_count()} * 3);
  for (size_t k = 0; k < measured.size(); ++k) {
    const size_t t = measured[k];
    progress("measuring step", k, measured.size());
    if (Status s = frames.read_step(t, original_xyz); !s.ok()) return fail(s.message());
    nav.positions(double(t), model_xyz);
    const auto slot = std::find(chosen.begin(), chosen.end(), t);
    for (Row& row : rows) {
      const std::span<const float> xyz(model_xyz.data(), size_t{row.vertices} * 3);
      auto r = hausdorff(original, original_xyz, row.topology, xyz, h);
      if (!r)
        return fail("step " + std::to_string(t) + ", " + std::to_string(row.vertices) +
                    " vertices: " + r.message());
      const Cell cell{r->percent(r->hausdorff), r->percent(r->mean), r->percent(r->rms),
                      r->diagonal};
      if (slot != chosen.end()) row.chosen[size_t(slot - chosen.begin())] = cell;
      if (k == 0 || cell.hausdorff_pct > row.max.hausdorff_pct) {
        row.max.hausdorff_pct = cell.hausdorff_pct;
        row.max.diagonal = cell.diagonal;
        row.max_step = t;
      }
      row.max.mean_pct = std::max(row.max.mean_pct, cell.mean_pct);
      row.max.rms_pct = std::max(row.max.rms_pct, cell.rms_pct);
    }
  }
  progress("measuring step", measured.size(), measured.size());

  const std::string max_label =
      max_over_all ? "max over all " + std::to_string(steps) + " steps" : "max over these steps";

  // The table (the paper's Table 2): rows = resolution, columns = steps and the max.
  std::string inputs = files->front();
  if (files->size() > 1) inputs += " … " + files->back();
  std::printf("original      %s (%zu steps, %u vertices, %zu faces)\n", inputs.c_str(), steps,
              original.vertex_count, original.faces.size());
  std::printf("model         %s (base %u vertices, %u splits)\n", dpm_path->c_str(),
              mesh->base_vertex_count, mesh->split_count());
  std::printf(
      "two-sided Hausdorff distance, %% of the bounding-box diagonal over all steps (%.4g)\n\n",
      h.reference_diagonal);
  std::printf("%10s %9s %9s", "% vertices", "vertices", "faces");
  for (size_t t : chosen) std::printf(" %11s", ("step " + std::to_string(t)).c_str());
  std::printf("  %s\n", max_label.c_str());
  for (const Row& row : rows) {
    std::printf("%10s %9u %9u", (format_number(row.ratio) + " %").c_str(), row.vertices, row.faces);
    for (const Cell& c : row.chosen) std::printf(" %11.4g", c.hausdorff_pct);
    std::printf("  %.4g (step %zu)\n", row.max.hausdorff_pct, row.max_step);
  }

  if (json_path) {
    Json j;
    j.begin_object();
    j.begin_array("original");
    for (const std::string& f : *files) j.item(f);
    j.end_array();
    j.value("model", *dpm_path);
    j.value("vertices", uint64_t{original.vertex_count});
    j.value("faces", uint64_t{original.faces.size()});
    j.value("steps", uint64_t{steps});
    j.value("seed", h.seed);
    j.value("model_diagonal", mesh->diagonal());
    j.begin_array("chosen_steps");
    for (size_t t : chosen) j.item(int64_t(t));
    j.end_array();
    j.value("max_over", max_over_all ? "all" : "chosen");
    j.begin_array("ratios");
    for (const Row& row : rows) {
      j.begin_object();
      j.value("ratio_pct", row.ratio);
      j.value("vertices", uint64_t{row.vertices});
      j.value("vertices_pct", 100.0 * row.vertices / mesh->full_vertex_count);
      j.value("faces", uint64_t{row.faces});
      j.value("level", uint64_t{row.level});
      j.value("level_error", row.error);
      j.value("level_error_pct", 100 * of_diagonal(row.error, mesh->diagonal()));
      j.begin_array("steps");
      for (size_t k = 0; k < chosen.size(); ++k) {
        const Cell& c = row.chosen[k];
        j.begin_object();
        j.value("step", uint64_t{chosen[k]});
        j.value("time", frames.step_time(chosen[k]));
        j.value("diagonal", c.diagonal);
        j.value("hausdorff_pct", c.hausdorff_pct);
        j.value("mean_pct", c.mean_pct);
        j.value("rms_pct", c.rms_pct);
        j.end_object();
      }
      j.end_array();
      j.begin_object("max");
      j.value("hausdorff_pct", row.max.hausdorff_pct);
      j.value("step", uint64_t{row.max_step});
      j.value("mean_pct", row.max.mean_pct);
      j.value("rms_pct", row.max.rms_pct);
      j.end_object();
      j.end_object();
    }
    j.end_array();
    j.end_object();
    if (Status s = write_file_atomically(*json_path, j.str() + "\n"); !s.ok())
      return fail(s.message());
    std::printf("\nwrote %s\n", json_path->c_str());
  }
  if (plot_path) {
    std::string model_name = *dpm_path;
    if (auto slash = model_name.find_last_of('/'); slash != std::string::npos)
      model_name = model_name.substr(slash + 1);
    const std::string svg = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n" +
                            svg_plot(rows, chosen, max_label, mesh->full_vertex_count,
                                     "dynpm eval: " + model_name + " against the original");
    if (Status s = write_file_atomically(*plot_path, svg); !s.ok()) return fail(s.message());
    std::printf("%swrote %s\n", json_path ? "" : "\n", plot_path->c_str());
  }
  return kExitOk;
}

}  // namespace dynpm::cli
