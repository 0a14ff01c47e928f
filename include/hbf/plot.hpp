// hbfriction — plots through gnuplot (`--plot FILE.png|FILE.svg` of the hbf commands).
//
// A plot is a list of curves drawn over one pair of axes. gnuplot renders it into a temporary
// file beside the target, which is renamed onto the target only when gnuplot succeeded: a
// failed plot never leaves a partial file.
#pragma once
#include <string>
#include <vector>

#include "hbf/continuation.hpp"
#include "hbf/post_processing.hpp"
#include "hbf/stability.hpp"

namespace hbf::io {

struct PlotCurve {
    enum class Style { line, dashed, points, markers };
    std::string title;          ///< legend entry (empty: none)
    std::vector<double> x, y;   ///< NaN in x or y breaks a line (e.g. between branches)
    Style style = Style::line;
    int point_type = 7;         ///< gnuplot point type for points/markers (7 dot, 6 circle, 8/9 triangles, 4 square, 2 cross)
};

struct PlotSpec {
    std::string title, xlabel, ylabel;
    std::vector<PlotCurve> curves;
    bool log_x = false, log_y = false;
    /// A heat map of scattered points: (heat_x[k], heat_y[k]) coloured by heat_z[k] on the
    /// palette (drawn first, under the curves; empty: none).
    std::vector<double> heat_x, heat_y, heat_z;
    std::string colorbar;       ///< label of the colour bar
    bool log_colorbar = false;
};

/// Throws InvalidInput naming `flag` unless the path ends in .png or .svg.
void check_plot_path(const std::string& flag, const std::string& path);

/// Throws std::runtime_error with an installation hint if gnuplot cannot be run.
void require_gnuplot();

/// Both checks above, before any work, for a `--plot`-style flag; nothing when `path` is empty.
void check_plot(const std::string& flag, const std::string& path);

/// Renders the plot into `path` (.png: pngcairo, .svg: svg, 900 x 600) through gnuplot,
/// atomically. Throws std::runtime_error (with gnuplot's message) on failure.
void write_plot(const std::string& path, const PlotSpec& spec);

/// y_max of DOF `dof` against w along an FRF: each branch drawn in order as a line, folds,
/// stick-slip transitions and samples marked (metrics[k] belongs to points[k]).
PlotSpec frf_plot(const std::vector<SolutionPoint>& points, const std::vector<PointMetrics>& metrics, int dof,
                  const std::string& title);
/// The same for an output: metrics[k].output_max[index], or, with index < 0, y_max of the
/// output's single DOF (model.hpp). With `stability` (one verdict per point), the branch is
/// drawn solid where stable and dashed where unstable (a segment between a stable and an
/// unstable point changes style at its middle; one that ends at a fold or an uncertain point,
/// the boundary itself, takes the style of its other end), and uncertain verdicts are marked.
PlotSpec frf_plot(const std::vector<SolutionPoint>& points, const std::vector<PointMetrics>& metrics,
                  const Output& output, int index, const BranchStability* stability, const std::string& title);

}  // namespace hbf::io
