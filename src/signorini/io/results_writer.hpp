// Writes what a run produces, after every converged increment, atomically: VTU files with a
// PVD collection, a CSV of reaction forces per set and increment, and a JSON summary whose
// status says whether the run is still going, finished, or failed (and why).
#pragma once
#include <map>
#include <string>
#include <vector>

#include "signorini/solver/analysis.hpp"

namespace signorini {

struct CheckResult {
  Check check;
  Real computed = 0;
  Real error = 0;  // relative (absolute if the expected value is 0)
  bool pass = false;
};

std::vector<CheckResult> evaluate_checks(const Analysis& analysis);

// The radius that best separates points inside a zone from those outside, given each
// point's radius and whether it is inside: the threshold with the fewest points on the wrong
// side (the mean of the midpoints between consecutive radii reaching that minimum); 0 when
// no point is inside. Used for the radius of a 3D contact or stick zone (component r).
Real separating_radius(std::vector<std::pair<Real, bool>> points);

// A slave node of several pairs (a tube's outer surface pressed by two plates, each its own
// pair) has one value in the whole mesh's contact fields: the state of the pair where it is
// most engaged. True when `a` is more engaged than `b`: in contact (closed or slipping) before
// open before far; in contact in both, the larger pressure; open in both, the smaller gap.
// Each pair's own files (contact_<name>_*.vtu and .csv) hold its states.
bool more_engaged(const ContactInterface::SlaveState& a, const ContactInterface::SlaveState& b);

class ResultsWriter {
 public:
  // `rank`: the MPI rank. Rank 0 writes every file; under mpirun with the cells shared out,
  // each other rank writes the ParaView piece of its own cells (every rank then calls these
  // functions at the same points: a piece's write is collective).
  ResultsWriter(const Model& model, std::string directory, int rank = 0);
  // The initial (undeformed) state at time 0, so every run has a PVD and a CSV from the start.
  void write_initial(const Analysis& a);
  void write_increment(const Analysis& a, const IncrementRecord& rec);
  // Final JSON (and the last VTU when vtu: last). `failure` empty when the run completed.
  void finish(const Analysis& a, const AnalysisSummary& s, const std::vector<CheckResult>& checks);
  // A run stopped by an error (an output file that could not be written, a disk full): the
  // summary so far with status `failed` and `why` as its failure, so that summary.json does not
  // go on saying `running`. Best effort (on a full disk this write may fail too): never throws.
  void record_error(const Analysis& a, const std::string& why) noexcept;
  const std::string& directory() const { return dir_; }
  std::string pvd_path() const { return dir_ + "/results.pvd"; }
  int vtu_count() const { return static_cast<int>(pvd_.size()); }

 private:
  void write_vtu(const Analysis& a, Real time, int step, int inc);
  // reactions.csv and the contact CSVs of an increment.
  void write_tables(const Analysis& a, const IncrementRecord& rec);
  void write_contact_csv(const Analysis& a, const IncrementRecord& rec);
  // The slave surface of each pair as its own mesh (facets as cells) with gap, pressure and
  // status, in contact_<pair>.pvd.
  void write_contact_vtu(const Analysis& a, Real time, int step, int inc);
  void write_json(const Analysis& a, const AnalysisSummary& s, const std::string& status,
                  const std::vector<CheckResult>& checks);
  const Model& model_;
  std::string dir_;
  std::vector<std::pair<Real, std::string>> pvd_;
  std::map<std::string, std::vector<std::pair<Real, std::string>>> contact_pvd_;  // per pair
  std::string csv_;
  IncrementRecord last_record_;
  bool have_last_ = false;
  bool shared_ = true;  // rank 0: writes the files that are not a rank's piece
};

}  // namespace signorini
