// hbfriction — figures through gnuplot (plot.hpp): curves over one pair of axes, rendered into a
// temporary file and moved onto the output under the output policy.
#include "hbf/plot.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>

#include "hbf/error.hpp"
#include "hbf/output_file.hpp"

namespace hbf::io {

namespace {
namespace fs = std::filesystem;

std::string extension_of(const std::string& path) {
    const std::string e = fs::path(path).extension().string();
    std::string lower;
    for (char c : e) lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return lower;
}

/// A gnuplot string literal (single quotes; a quote is doubled).
std::string quoted(const std::string& text) {
    std::string out = "'";
    for (char c : text) out += c == '\'' ? std::string("''") : std::string(1, c);
    return out + "'";
}

std::string unique_suffix() {
    std::random_device device;
    return std::to_string(::getpid()) + "-" + std::to_string(device());
}

std::string number(double v) {
    if (!std::isfinite(v)) return "NaN";
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.10g", v);
    return buffer;
}
}  // namespace

void check_plot_path(const std::string& flag, const std::string& path) {
    const std::string e = extension_of(path);
    if (e != ".png" && e != ".svg")
        throw InvalidInput(flag + " = '" + path + "' has an unknown image type '" + e + "': allowed .png or .svg");
}

void require_gnuplot() {
    if (std::system("gnuplot --version >/dev/null 2>&1") != 0)
        throw std::runtime_error("gnuplot is needed for plots and could not be run (Debian: apt-get install "
                                 "gnuplot-nox; scripts/install-deps.sh installs it)");
}

void check_plot(const std::string& flag, const std::string& path) {
    if (path.empty()) return;
    check_plot_path(flag, path);
    require_gnuplot();
}

void write_plot(const std::string& path, const PlotSpec& spec) {
    check_plot_path("plot", path);
    // A symlink stays one: the image replaces its final target.
    const fs::path target = fs::is_symlink(path) ? fs::canonical(path) : fs::path(path);
    const fs::path directory = target.has_parent_path() ? target.parent_path() : fs::path(".");
    const std::string suffix = unique_suffix();
    const fs::path image = directory / ("." + target.filename().string() + ".tmp-" + suffix + extension_of(path));
    // Every file of the drawing beside the image (a directory the output policy checked), never
    // in TMPDIR, which may not exist; none outlives this function, signals are held meanwhile.
    const HeldSignals quiet;
    const fs::path script = directory / ("." + target.filename().string() + ".tmp-" + suffix + ".gp");
    const fs::path log = directory / ("." + target.filename().string() + ".tmp-" + suffix + ".log");
    auto cleanup = [&] {
        std::error_code ignored;
        fs::remove(image, ignored);
        fs::remove(script, ignored);
        fs::remove(log, ignored);
    };
    {
        std::ofstream gp(script);
        gp << (extension_of(path) == ".png" ? "set terminal pngcairo size 900,600 enhanced font 'sans,11'\n"
                                             : "set terminal svg size 900,600 enhanced font 'sans,11' background 'white'\n");
        gp << "set output " << quoted(image.string()) << "\n"
           << "set grid\nset key top right\n"
           << "set title " << quoted(spec.title) << " noenhanced\n"
           << "set xlabel " << quoted(spec.xlabel) << " noenhanced\n"
           << "set ylabel " << quoted(spec.ylabel) << " noenhanced\n";
        if (spec.log_x) gp << "set logscale x\n";
        if (spec.log_y) gp << "set logscale y\n";
        if (!spec.colorbar.empty()) gp << "set cblabel " << quoted(spec.colorbar) << " noenhanced\nset palette rgb 33,13,10\n";
        if (spec.log_colorbar) gp << "set logscale cb\n";
        std::vector<std::string> plots;
        if (!spec.heat_x.empty()) {
            gp << "$heat << EOD\n";
            for (std::size_t k = 0; k < spec.heat_x.size() && k < spec.heat_y.size() && k < spec.heat_z.size(); ++k)
                if (std::isfinite(spec.heat_x[k]) && std::isfinite(spec.heat_y[k]) && std::isfinite(spec.heat_z[k]))
                    gp << number(spec.heat_x[k]) << ' ' << number(spec.heat_y[k]) << ' ' << number(spec.heat_z[k]) << '\n';
            gp << "EOD\n";
            plots.push_back("$heat using 1:2:3 with points pt 5 ps 0.6 lc palette notitle");
        }
        for (std::size_t c = 0; c < spec.curves.size(); ++c) {
            const PlotCurve& curve = spec.curves[c];
            if (curve.x.empty()) continue;
            const std::string block = "$curve" + std::to_string(c);
            gp << block << " << EOD\n";
            for (std::size_t k = 0; k < curve.x.size() && k < curve.y.size(); ++k) {
                if (!std::isfinite(curve.x[k]) || !std::isfinite(curve.y[k]))
                    gp << '\n';  // a blank line breaks the line (a gap, or the next branch)
                else
                    gp << number(curve.x[k]) << ' ' << number(curve.y[k]) << '\n';
            }
            gp << "EOD\n";
            std::string style;
            switch (curve.style) {
                case PlotCurve::Style::line: style = "with lines lw 2"; break;
                case PlotCurve::Style::dashed: style = "with lines lw 2 dt 2"; break;
                case PlotCurve::Style::points: style = "with points pt " + std::to_string(curve.point_type) + " ps 0.5"; break;
                case PlotCurve::Style::markers: style = "with points pt " + std::to_string(curve.point_type) + " ps 1.5 lw 2"; break;
            }
            plots.push_back(block + " using 1:2 " + style + " title " + quoted(curve.title) + " noenhanced");
        }
        if (plots.empty()) plots.push_back("NaN notitle");
        gp << "plot ";
        for (std::size_t k = 0; k < plots.size(); ++k) gp << (k ? ", \\\n     " : "") << plots[k];
        gp << "\nunset output\n";
        if (!gp) {
            cleanup();
            throw std::runtime_error("cannot write the gnuplot script " + script.string());
        }
    }
    const std::string command = "gnuplot " + quoted(script.string()) + " >" + quoted(log.string()) + " 2>&1";
    const int status = std::system(command.c_str());
    std::error_code error;
    if (status != 0 || !fs::exists(image) || fs::file_size(image, error) == 0) {
        std::ifstream in(log);
        std::stringstream message;
        message << in.rdbuf();
        cleanup();
        throw std::runtime_error("gnuplot could not draw " + path + (message.str().empty() ? "" : ": " + message.str()));
    }
    fs::rename(image, target, error);
    if (error) {
        cleanup();
        throw std::runtime_error("cannot write " + path + ": " + error.message());
    }
    cleanup();
}

PlotSpec frf_plot(const std::vector<SolutionPoint>& points, const std::vector<PointMetrics>& metrics, int dof,
                  const std::string& title) {
    return frf_plot(points, metrics, Output::dof(dof), -1, nullptr, title);
}

PlotSpec frf_plot(const std::vector<SolutionPoint>& points, const std::vector<PointMetrics>& metrics,
                  const Output& output, int index, const BranchStability* stability, const std::string& title) {
    PlotSpec spec;
    spec.title = title;
    spec.xlabel = "w";
    const int dof = output.single_dof();
    spec.ylabel = output.name() + "_max = max over one period of |" + output.name() + "(t)|";
    PlotCurve branch{"harmonic balance (branch in order)", {}, {}, PlotCurve::Style::line, 7};
    PlotCurve folds{"folds", {}, {}, PlotCurve::Style::markers, 9};
    PlotCurve transitions{"stick-slip transitions", {}, {}, PlotCurve::Style::markers, 6};
    PlotCurve samples{"samples (--at)", {}, {}, PlotCurve::Style::markers, 2};
    PlotCurve caps{"amplitude cap: unbounded resonance, the branch stops", {}, {}, PlotCurve::Style::markers, 5};
    PlotCurve unstable{"unstable (Floquet: a perturbation grows)", {}, {}, PlotCurve::Style::dashed, 7};
    PlotCurve uncertain{"stability uncertain", {}, {}, PlotCurve::Style::markers, 12};
    PlotCurve bifurcations{"branch point, period doubling or Neimark-Sacker (first point past it)", {}, {},
                           PlotCurve::Style::markers, 3};
    if (stability) branch.title = "harmonic balance, stable (branch in order)";
    const double NaN = std::nan("");
    auto value_at = [&](std::size_t k) {
        return index >= 0 ? metrics[k].output_max[static_cast<std::size_t>(index)]
                          : metrics[k].y_max[static_cast<std::size_t>(dof)];
    };
    auto is_unstable = [&](std::size_t k) {
        return stability && k < stability->points.size() && stability->points[k].stability == Stability::unstable;
    };
    // A segment of the branch in one style: continues the curve's last piece if it ends there.
    auto segment = [&](PlotCurve& c, double x0, double y0, double x1, double y1) {
        if (c.x.empty() || c.x.back() != x0 || c.y.back() != y0) {
            if (!c.x.empty()) {
                c.x.push_back(NaN);
                c.y.push_back(NaN);
            }
            c.x.push_back(x0);
            c.y.push_back(y0);
        }
        c.x.push_back(x1);
        c.y.push_back(y1);
    };
    int last_branch = 0;
    std::size_t last = 0;
    for (std::size_t k = 0; k < points.size(); ++k) {
        const SolutionPoint& p = points[k];
        const double value = value_at(k);
        if (p.kind == PointKind::sample) {
            samples.x.push_back(p.omega);
            samples.y.push_back(value);
            continue;
        }
        if (stability && k < stability->points.size() && stability->points[k].stability == Stability::uncertain) {
            uncertain.x.push_back(p.omega);
            uncertain.y.push_back(value);
        }
        if (last_branch == p.branch) {
            const double x0 = points[last].omega, y0 = value_at(last);
            // A fold or an uncertain point is the boundary itself: the segment takes the style
            // of its other end; otherwise the style changes at the segment's middle.
            auto boundary = [&](std::size_t j) {
                return points[j].kind == PointKind::fold ||
                       (stability && j < stability->points.size() &&
                        stability->points[j].stability == Stability::uncertain);
            };
            const bool from_unstable = boundary(last) && !boundary(k) ? is_unstable(k) : is_unstable(last);
            const bool to_unstable = boundary(k) && !boundary(last) ? is_unstable(last) : is_unstable(k);
            PlotCurve& from = from_unstable ? unstable : branch;
            PlotCurve& to = to_unstable ? unstable : branch;
            if (&from == &to) {
                segment(from, x0, y0, p.omega, value);
            } else {  // the style changes at the segment's middle
                const double xm = 0.5 * (x0 + p.omega), ym = 0.5 * (y0 + value);
                segment(from, x0, y0, xm, ym);
                segment(to, xm, ym, p.omega, value);
            }
        } else if (k + 1 == points.size() || points[k + 1].branch != p.branch ||
                   points[k + 1].kind == PointKind::sample) {
            segment(is_unstable(k) ? unstable : branch, p.omega, value, p.omega, value);  // a lone point
        }
        last_branch = p.branch;
        last = k;
        if (p.kind == PointKind::fold) {
            folds.x.push_back(p.omega);
            folds.y.push_back(value);
        } else if (p.kind == PointKind::transition) {
            transitions.x.push_back(p.omega);
            transitions.y.push_back(value);
        } else if (p.kind == PointKind::cap) {
            caps.x.push_back(p.omega);
            caps.y.push_back(value);
        } else if (p.kind == PointKind::branch_point || p.kind == PointKind::period_doubling ||
                   p.kind == PointKind::neimark_sacker) {
            bifurcations.x.push_back(p.omega);
            bifurcations.y.push_back(value);
        }
    }
    spec.curves = {branch, folds, transitions, samples, caps};
    if (stability) {
        spec.curves.push_back(unstable);
        spec.curves.push_back(uncertain);
        spec.curves.push_back(bifurcations);
    }
    return spec;
}

}  // namespace hbf::io
