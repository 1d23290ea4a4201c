#include "study/io/results_file.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <numeric>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>

#include "core/run/simulation.hpp"
#include "metrics/verdict.hpp"
#include "study/formats/hdf5_file.hpp"
#include "study/formats/text_file.hpp"
#include "study/io/history_file.hpp"
#include "study/studies/spectral_study.hpp"

namespace impactid {
namespace {

// Written as the root attribute `format`; read_results() accepts exactly this. Change it when
// the layout changes in a way an older reader would misread.
constexpr const char* kFormat = "impactid-results-1";
constexpr const char* kStatus = "status";
constexpr const char* kRoleParameter = "parameter";
constexpr const char* kRoleIndicator = "indicator";

// The status codes are RunStatus's values, with kStatusNotDone before them.
static_assert(static_cast<int>(RunStatus::ok) == 0 && static_cast<int>(RunStatus::unstable) == 1 &&
              static_cast<int>(RunStatus::failed) == 2);
constexpr std::array<int, 4> kStatusCodes{kStatusNotDone, 0, 1, 2};

// CF flag_meanings: one word per code, from RunStatus's own names.
std::string status_meanings() {
  return std::string("not_done ") + to_string(RunStatus::ok) + " " +
         to_string(RunStatus::unstable) + " " + to_string(RunStatus::failed);
}

// Root attributes with a fixed meaning; any other root attribute is a study attribute.
constexpr std::array<const char*, 12> kFixedAttributes{
    "format", "impactid_version", "git_revision",    "plan", "plan_name",    "study_kind",
    "method", "threads",          "run_wall_time_s", "date", "points_total", "points_done"};

bool is_fixed_attribute(const std::string& name) {
  return std::find(kFixedAttributes.begin(), kFixedAttributes.end(), name) !=
         kFixedAttributes.end();
}

std::size_t grid_size(const std::vector<ResultDimension>& dimensions) {
  return std::accumulate(
      dimensions.begin(), dimensions.end(), std::size_t{1},
      [](std::size_t n, const ResultDimension& d) { return n * d.values.size(); });
}

bool is_status_code(int value) {
  return std::find(kStatusCodes.begin(), kStatusCodes.end(), value) != kStatusCodes.end();
}

// A name that becomes an HDF5 dataset (and, for indicators, a CSV file name).
std::optional<std::string> bad_name(const std::string& what, const std::string& name) {
  if (name.empty()) return what + " with an empty name";
  if (name.find('/') != std::string::npos || name == "." || name == "..") {
    return what + " \"" + name + "\": a name must not contain '/' or be \".\" or \"..\"";
  }
  return std::nullopt;
}

// Why a table cannot be stored, or nullopt. Shared by write_results and export_csv, which
// wrap the message in their own error type; a table built by the study code never fails it.
std::optional<std::string> inconsistency(const StudyResults& r) {
  if (r.dimensions.empty()) return "a results table needs at least one dimension";
  const std::size_t size = grid_size(r.dimensions);
  std::set<std::string> datasets{kStatus};
  const auto claim = [&](const std::string& what,
                         const std::string& name) -> std::optional<std::string> {
    if (auto bad = bad_name(what, name)) return bad;
    if (!datasets.insert(name).second) return what + " \"" + name + "\": name used twice";
    return std::nullopt;
  };
  for (const ResultDimension& d : r.dimensions) {
    if (auto bad = claim("dimension", d.name)) return bad;
    if (!d.labels.empty() && d.labels.size() != d.values.size()) {
      return "dimension " + d.name + " has " + std::to_string(d.labels.size()) + " labels for " +
             std::to_string(d.values.size()) + " values";
    }
  }
  if (r.status.size() != size) {
    return "status has " + std::to_string(r.status.size()) + " values, the grid " +
           std::to_string(size) + " points";
  }
  for (std::size_t i = 0; i < r.status.size(); ++i) {
    if (!is_status_code(r.status[i])) {
      return "status[" + std::to_string(i) + "] = " + std::to_string(r.status[i]) +
             ": must be one of -1 (not done), 0 (ok), 1 (unstable), 2 (failed)";
    }
  }
  for (const auto* columns : {&r.parameters, &r.indicators}) {
    for (const ResultColumn& c : *columns) {
      if (auto bad = claim("column", c.name)) return bad;
      if (c.values.size() != size) {
        return "column \"" + c.name + "\" has " + std::to_string(c.values.size()) +
               " values, the grid " + std::to_string(size) + " points";
      }
    }
  }
  std::set<std::string> attributes;
  const auto claim_attribute = [&](const std::string& name) -> std::optional<std::string> {
    if (name.empty()) return "a study attribute with an empty name";
    if (is_fixed_attribute(name) || name == kChecksumAttribute) {
      return "study attribute \"" + name + "\": reserved name";
    }
    if (!attributes.insert(name).second) return "study attribute \"" + name + "\": used twice";
    return std::nullopt;
  };
  for (const auto& [name, value] : r.numeric_attributes) {
    if (auto bad = claim_attribute(name)) return bad;
  }
  for (const auto& [name, value] : r.text_attributes) {
    if (auto bad = claim_attribute(name)) return bad;
  }
  return std::nullopt;
}

void write_column(Hdf5Writer& file, const ResultColumn& c, const Hdf5Dims& grid, const char* role) {
  file.dataset(c.name, c.values, grid);
  file.attribute(c.name, "units", c.units);
  file.attribute(c.name, "long_name", c.long_name);
  if (!c.definition.empty()) file.attribute(c.name, "definition", c.definition);
  file.attribute(c.name, "role", std::string(role));
}

// --- reading ---------------------------------------------------------------------------------

class ResultsReader {
 public:
  explicit ResultsReader(const std::filesystem::path& path) : path_(path), file_(path) {}

  StudyResults read() {
    check_format();
    StudyResults r;
    r.impactid_version = text("impactid_version");
    r.git_revision = text("git_revision");
    r.plan_text = text("plan");
    r.plan_name = text("plan_name");
    r.study_kind = text("study_kind");
    r.method = text("method");
    r.date = text("date");
    require("/", "threads");
    r.threads = file_.attribute_long("/", "threads");
    require("/", "run_wall_time_s");
    r.wall_time_s = file_.attribute_double("/", "run_wall_time_s");
    // points_total and points_done are derived from `status`: informational only.
    for (const std::string& name : file_.attribute_names("/")) {
      if (is_fixed_attribute(name)) continue;
      if (file_.attribute_is_text("/", name)) {
        r.text_attributes.emplace_back(name, file_.attribute_string("/", name));
      } else {
        r.numeric_attributes.emplace_back(name, file_.attribute_double("/", name));
      }
    }

    if (!file_.exists(kStatus)) throw error("no `status` dataset");
    const Hdf5Dims grid = file_.shape(kStatus);
    if (grid.empty()) throw error("`status` is a scalar; expected one dimension per axis");
    for (unsigned d = 0; d < grid.size(); ++d) r.dimensions.push_back(dimension(grid, d));
    r.status = file_.ints(kStatus);
    for (std::size_t i = 0; i < r.status.size(); ++i) {
      if (!is_status_code(r.status[i])) {
        throw error("status[" + std::to_string(i) + "] = " + std::to_string(r.status[i]) +
                    " is not a status code (-1, 0, 1, 2)");
      }
    }

    for (const std::string& name : file_.members("/")) {
      if (name == kStatus || !file_.has_attribute(name, "role")) continue;  // axes, extras
      const std::string role = file_.attribute_string(name, "role");
      if (role != kRoleParameter && role != kRoleIndicator) {
        throw error(name + ": role \"" + role + "\" is neither parameter nor indicator");
      }
      if (file_.shape(name) != grid) throw error(name + ": not shaped like `status`");
      ResultColumn c;
      c.name = name;
      c.units = text(name, "units");
      c.long_name = text(name, "long_name");
      if (file_.has_attribute(name, "definition")) {
        c.definition = file_.attribute_string(name, "definition");
      }
      c.values = file_.doubles(name);
      (role == kRoleParameter ? r.parameters : r.indicators).push_back(std::move(c));
    }
    return r;
  }

 private:
  Hdf5Error error(const std::string& message) const {
    return Hdf5Error(path_.string() + ": " + message);
  }

  void require(const std::string& object, const std::string& name) const {
    if (!file_.has_attribute(object, name)) {
      throw error(object == "/" ? "missing root attribute `" + name + "`"
                                : object + ": missing attribute `" + name + "`");
    }
  }

  std::string text(const std::string& name) const { return text("/", name); }
  std::string text(const std::string& object, const std::string& name) const {
    require(object, name);
    return file_.attribute_string(object, name);
  }

  // impactid's other HDF5 files are named, so that a wrong file given is recognised.
  void check_format() const {
    if (!file_.has_attribute("/", "format")) {
      if (is_history_file(path_)) {
        throw error("not an impactid results file: a history file (impactid simulate --history)");
      }
      throw error("not an impactid results file (no root attribute `format`)");
    }
    const std::string format =
        file_.attribute_is_text("/", "format") ? file_.attribute_string("/", "format") : "";
    if (format == kSpectralFormat) {
      throw error("not an impactid results file: a spectral file (format \"" + format +
                  "\", impactid spectral)");
    }
    if (format != kFormat) {
      throw error("format \"" + format + "\" is not " + kFormat +
                  " (a different kind of file, or written by another impactid version)");
    }
  }

  // The axis attached to dimension d of `status`.
  ResultDimension dimension(const Hdf5Dims& grid, unsigned d) const {
    const std::vector<std::string> scales = file_.attached_scales(kStatus, d);
    if (scales.size() != 1) {
      throw error("dimension " + std::to_string(d) + " of `status` has " +
                  std::to_string(scales.size()) + " dimension scales attached, expected one");
    }
    ResultDimension dim;
    dim.name = scales[0].substr(scales[0].rfind('/') + 1);
    if (file_.shape(dim.name) != Hdf5Dims{grid[d]}) {
      throw error(dim.name + ": length does not match dimension " + std::to_string(d) +
                  " of `status`");
    }
    dim.units = text(dim.name, "units");
    dim.values = file_.doubles(dim.name);
    const std::vector<std::string> attributes = file_.attribute_names(dim.name);
    if (std::find(attributes.begin(), attributes.end(), "flag_meanings") != attributes.end()) {
      std::istringstream words(text(dim.name, "flag_meanings"));
      for (std::string word; words >> word;) dim.labels.push_back(word);
      if (dim.labels.size() != dim.values.size()) {
        throw error(dim.name + ": flag_meanings has " + std::to_string(dim.labels.size()) +
                    " words for " + std::to_string(dim.values.size()) + " values");
      }
    }
    return dim;
  }

  std::filesystem::path path_;
  Hdf5Reader file_;
};

// --- CSV -------------------------------------------------------------------------------------

// RFC 4180: a field holding a comma, quote or line break is quoted, quotes doubled.
std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (const char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

// "p_max[MPa]"; a dimensionless quantity (units "1" or empty) is just its name.
std::string csv_label(const std::string& name, const std::string& units) {
  return csv_field(units.empty() || units == "1" ? name : name + "[" + units + "]");
}

// The shortest text that reads back as the same double (std::to_chars without a precision):
// 0.1, not 0.10000000000000001. Locale-independent. NaN (not done, not ok, or undefined) is
// written "nan", whatever its sign bit.
void put_number(std::ostream& out, double value) {
  if (std::isnan(value)) {
    out << "nan";
    return;
  }
  char buffer[32];
  const auto end = std::to_chars(buffer, buffer + sizeof buffer, value).ptr;
  out.write(buffer, end - buffer);
}

// A column with no number at any point (an indicator that does not apply to the scene, such as
// far_contact_episodes without a far wall) is left out of the CSV files.
bool all_nan(const ResultColumn& c) {
  return std::all_of(c.values.begin(), c.values.end(), [](double v) { return std::isnan(v); });
}

// The k-th value of a dimension as CSV: a number, or a choice axis's word.
void put_value(std::ostream& out, const ResultDimension& dimension, std::size_t k) {
  if (dimension.labels.empty()) {
    put_number(out, dimension.values[k]);
  } else {
    out << csv_field(dimension.labels[k]);
  }
}

// An indicator's value; the verdict column (study/studies/sweep.hpp) as its word, "accurate".
void put_indicator(std::ostream& out, const ResultColumn& c, std::size_t i) {
  const double v = c.values[i];
  if (c.name == kVerdictColumn && v >= 0 && v < static_cast<double>(all_verdicts().size()) &&
      v == std::floor(v)) {
    out << to_string(all_verdicts()[static_cast<std::size_t>(v)]);
    return;
  }
  put_number(out, v);
}

void write_points(std::ostream& out, const StudyResults& r) {
  std::string header;
  const auto add = [&](const std::string& label) { header += (header.empty() ? "" : ",") + label; };
  for (const ResultDimension& d : r.dimensions) add(csv_label(d.name, d.units));
  for (const ResultColumn& c : r.parameters) {
    if (!all_nan(c)) add(csv_label(c.name, c.units));
  }
  add(kStatus);
  for (const ResultColumn& c : r.indicators) {
    if (!all_nan(c)) add(csv_label(c.name, c.units));
  }
  out << header << '\n';

  std::vector<std::size_t> index(r.dimensions.size(), 0);  // of the point, last axis fastest
  for (std::size_t i = 0; i < r.status.size(); ++i) {
    for (std::size_t d = 0; d < index.size(); ++d) {
      if (d > 0) out << ',';
      put_value(out, r.dimensions[d], index[d]);
    }
    for (const ResultColumn& c : r.parameters) {
      if (all_nan(c)) continue;
      out << ',';
      put_number(out, c.values[i]);
    }
    out << ',' << r.status[i];
    for (const ResultColumn& c : r.indicators) {
      if (all_nan(c)) continue;
      out << ',';
      put_indicator(out, c, i);
    }
    out << '\n';
    for (std::size_t d = index.size(); d-- > 0;) {
      if (++index[d] < r.dimensions[d].values.size()) break;
      index[d] = 0;
    }
  }
}

void write_matrix(std::ostream& out, const StudyResults& r, const ResultColumn& c) {
  const ResultDimension& rows = r.dimensions[0];
  const ResultDimension& columns = r.dimensions[1];
  out << csv_field(rows.name + "\\" + columns.name);
  for (std::size_t j = 0; j < columns.values.size(); ++j) {
    out << ',';
    put_value(out, columns, j);
  }
  out << '\n';
  for (std::size_t i = 0; i < rows.values.size(); ++i) {
    put_value(out, rows, i);
    for (std::size_t j = 0; j < columns.values.size(); ++j) {
      out << ',';
      put_number(out, c.values[i * columns.values.size() + j]);
    }
    out << '\n';
  }
}

}  // namespace

namespace {

void write_results_file(const std::filesystem::path& path, const StudyResults& results,
                        bool compressed) {
  if (const auto problem = inconsistency(results)) {
    throw Hdf5Error(path.string() + ": not written: " + *problem);
  }
  const StudyResults& r = results;
  Hdf5Writer file(path);  // removes its temporary file if anything below throws
  file.compress_large_datasets(compressed);

  file.attribute("/", "format", std::string(kFormat));
  file.attribute("/", "impactid_version", r.impactid_version);
  file.attribute("/", "git_revision", r.git_revision);
  file.attribute("/", "plan", r.plan_text);
  file.attribute("/", "plan_name", r.plan_name);
  file.attribute("/", "study_kind", r.study_kind);
  file.attribute("/", "method", r.method);
  file.attribute("/", "threads", r.threads);
  file.attribute("/", "run_wall_time_s", r.wall_time_s);
  file.attribute("/", "date", r.date);
  file.attribute("/", "points_total", r.points_total());
  file.attribute("/", "points_done", r.points_done());
  for (const auto& [name, value] : r.numeric_attributes) file.attribute("/", name, value);
  for (const auto& [name, value] : r.text_attributes) file.attribute("/", name, value);

  Hdf5Dims grid;
  for (const ResultDimension& d : r.dimensions) {
    file.dataset(d.name, d.values, Hdf5Dims{d.values.size()});
    file.attribute(d.name, "units", d.units);
    if (!d.labels.empty()) {
      std::vector<int> codes(d.labels.size());
      std::string meanings;
      for (std::size_t k = 0; k < d.labels.size(); ++k) {
        codes[k] = static_cast<int>(k);
        meanings += (k ? " " : "") + d.labels[k];
      }
      file.attribute(d.name, "flag_values", std::span<const int>(codes));
      file.attribute(d.name, "flag_meanings", meanings);
    }
    file.dimension_scale(d.name, d.name);  // NAME = the variable's name: a netCDF coordinate
    grid.push_back(d.values.size());
  }

  file.dataset(kStatus, r.status, grid);
  file.attribute(kStatus, "long_name", std::string("run status of the point"));
  file.attribute(kStatus, "definition",
                 std::string("-1: not run yet; else the RunStatus of the simulation: 0 ok, "
                             "1 unstable (non-finite value or energy bound exceeded), 2 failed "
                             "(the method could not start)"));
  file.attribute(kStatus, "flag_values", std::span<const int>(kStatusCodes));
  file.attribute(kStatus, "flag_meanings", status_meanings());
  for (const ResultColumn& c : r.parameters) write_column(file, c, grid, kRoleParameter);
  for (const ResultColumn& c : r.indicators) write_column(file, c, grid, kRoleIndicator);

  std::vector<std::string> gridded{kStatus};
  for (const auto* columns : {&r.parameters, &r.indicators}) {
    for (const ResultColumn& c : *columns) gridded.push_back(c.name);
  }
  for (const std::string& name : gridded) {
    for (unsigned d = 0; d < r.dimensions.size(); ++d) {
      file.attach_scale(name, r.dimensions[d].name, d);
    }
  }
  file.commit();
}

}  // namespace

void write_results(const std::filesystem::path& path, const StudyResults& results) {
  write_results_file(path, results, false);
}

void write_results_compressed(const std::filesystem::path& path, const StudyResults& results) {
  write_results_file(path, results, true);
}

StudyResults read_results(const std::filesystem::path& path) {
  return ResultsReader(path).read();
}

std::vector<std::string> export_csv(const StudyResults& results,
                                    const std::filesystem::path& directory) {
  if (const auto problem = inconsistency(results)) {
    throw std::runtime_error(directory.string() + ": not exported: " + *problem);
  }
  const bool matrices = results.dimensions.size() == 2;
  if (matrices) {
    for (const ResultColumn& c : results.indicators) {
      if (c.name == "points") {
        throw std::runtime_error((directory / "points.csv").string() +
                                 ": the indicator \"points\" would overwrite the point table");
      }
    }
  }
  std::error_code ec;
  std::filesystem::create_directories(directory, ec);
  if (ec || !std::filesystem::is_directory(directory)) {
    throw std::runtime_error(directory.string() + ": cannot create the folder" +
                             (ec ? ": " + ec.message() : std::string()));
  }
  write_text_atomically(directory / "points.csv",
                        [&](std::ostream& out) { write_points(out, results); });
  std::vector<std::string> skipped;
  for (const auto* columns : {&results.parameters, &results.indicators}) {
    for (const ResultColumn& c : *columns) {
      if (all_nan(c)) skipped.push_back(c.name);
    }
  }
  if (!matrices) return skipped;
  for (const ResultColumn& c : results.indicators) {
    if (all_nan(c)) continue;
    write_text_atomically(directory / (c.name + ".csv"),
                          [&](std::ostream& out) { write_matrix(out, results, c); });
  }
  return skipped;
}

}  // namespace impactid
