// What the rows of a least-squares problem say about it: the first
// non-finite model value, and how many residuals are distinct; and the
// sample of rows a large problem's starts are solved on.
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "fitting/least_squares.h"
#include "io/table.h"

namespace clothfit {

std::vector<uint32_t> SampleRows(size_t n, size_t m) {
  std::vector<uint32_t> out;
  if (m >= n) {
    out.resize(n);
    for (size_t i = 0; i < n; ++i) out[i] = static_cast<uint32_t>(i);
    return out;
  }
  out.reserve(m);
  std::mt19937_64 random(0x5eed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  // Algorithm S: row i is taken with probability (wanted) / (left).
  for (size_t i = 0; i < n && out.size() < m; ++i) {
    if (static_cast<double>(n - i) * u(random) <
        static_cast<double>(m - out.size())) {
      out.push_back(static_cast<uint32_t>(i));
    }
  }
  return out;
}

void PredictAll(const LeastSquaresProblem& lsq, const std::vector<double>& x,
                std::vector<double>* model, std::vector<double>* measured,
                std::vector<const TableRow*>* rows) {
  lsq.predict(x, [&](double m, double d, const TableRow* row) {
    model->push_back(m);
    measured->push_back(d);
    if (rows) rows->push_back(row);
  });
}

std::string NonFiniteRow(const LeastSquaresProblem& lsq,
                         const std::vector<double>& x) {
  std::vector<double> model, measured;
  std::vector<const TableRow*> rows;
  PredictAll(lsq, x, &model, &measured, &rows);
  for (size_t i = 0; i < model.size(); ++i) {
    if (std::isfinite(model[i]) && std::isfinite(model[i] - measured[i])) {
      continue;
    }
    const TableRow& row = *rows[i];
    std::ostringstream out;
    out.precision(6);
    out << "the model value is " << model[i] << " (data " << measured[i]
        << ") at ";
    if (row.source_line > 0) {
      out << "line " << row.source_line << " of the table";
    } else {
      out << "a row made in memory";
    }
    out << ", wi (" << row.wi.x << ", " << row.wi.y << ", " << row.wi.z
        << "), wo (" << row.wo.x << ", " << row.wo.y << ", " << row.wo.z
        << "), with";
    for (size_t k = 0; k < lsq.specs.size() && k < x.size(); ++k) {
      out << (k ? ", " : " ") << lsq.specs[k].name << " = " << x[k];
    }
    return out.str();
  }
  return "";
}

int DistinctResiduals(const LeastSquaresProblem& lsq,
                      const std::vector<double>& x, int residuals, int enough) {
  std::vector<const TableRow*> rows;
  if (lsq.row) {
    for (size_t i = 0; i < lsq.rows; ++i) rows.push_back(lsq.row(i));
  } else {
    std::vector<double> model, measured;
    PredictAll(lsq, x, &model, &measured, &rows);
  }
  // A row's pairs are its channels; rows at one place (directions, texel,
  // normal) repeat one measurement.
  using Place = std::tuple<double, double, double, double, double, double, int,
                           int, double, double, double>;
  std::set<const TableRow*> seen;
  std::set<Place> places;
  for (const TableRow* row : rows) {
    if (row == nullptr || !seen.insert(row).second) continue;
    places.insert({row->wi.x, row->wi.y, row->wi.z, row->wo.x, row->wo.y,
                   row->wo.z, row->s, row->t, row->normal.x, row->normal.y,
                   row->normal.z});
    // Each place has at least one residual: enough of them settle it.
    if (static_cast<int>(places.size()) >= enough) return residuals;
  }
  if (seen.empty() || places.size() == seen.size()) return residuals;
  return static_cast<int>(static_cast<double>(residuals) * places.size() /
                          seen.size());
}

}  // namespace clothfit
