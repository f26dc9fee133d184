#include "VoidFill.h"

#include "MembraneFill.h"

#include "terrain/base/Assert.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace terrain::io::detail {
namespace {

// Union-find over the runs found so far; a set's root is its first run, so the voids come out
// in the order of their first sample whatever order the unions happen in.
std::int64_t rootOf(std::vector<std::int64_t>& parent, std::int64_t i) {
    while (parent[static_cast<std::size_t>(i)] != i) {
        auto& p = parent[static_cast<std::size_t>(i)];
        p = parent[static_cast<std::size_t>(p)];  // path halving
        i = p;
    }
    return i;
}

void unite(std::vector<std::int64_t>& parent, std::int64_t a, std::int64_t b) {
    a = rootOf(parent, a);
    b = rootOf(parent, b);
    if (a == b) return;
    if (b < a) std::swap(a, b);
    parent[static_cast<std::size_t>(b)] = a;
}

}  // namespace

Result<VoidFill> VoidFill::find(DemReader& reader) {
    const ReadWindow read = [&reader](std::int64_t x0, std::int64_t y0, std::int64_t width,
                                      std::int64_t rows, std::span<float> out) {
        return reader.readWindow(x0, y0, width, rows, out);
    };
    return find(reader.info().width, reader.info().height, read);
}

Result<VoidFill> VoidFill::find(std::int64_t width, std::int64_t height, const ReadWindow& read,
                                const Beneath* beneath) {
    VoidFill fill;
    fill.m_rowRuns.assign(static_cast<std::size_t>(height + 1), 0);
    std::vector<std::int64_t> parent;  // of each run
    const std::int64_t bandRows = std::max<std::int64_t>(1, kMaxSolveSamples / width);
    std::vector<float> band;
    std::int64_t previous = 0;  // the previous row's first run
    for (std::int64_t y = 0; y < height; y += bandRows) {
        const std::int64_t rows = std::min(bandRows, height - y);
        band.resize(static_cast<std::size_t>(rows * width));
        if (Status got = read(0, y, width, rows, band); !got) return got.error();
        for (std::int64_t r = 0; r < rows; ++r) {
            const float* row = band.data() + r * width;
            const auto first = static_cast<std::int64_t>(fill.m_runs.size());
            fill.m_rowRuns[static_cast<std::size_t>(y + r)] = first;
            for (std::int64_t x = 0; x < width;) {
                if (!std::isnan(row[x])) {
                    ++x;
                    continue;
                }
                Run run;
                run.x0 = x;
                while (x < width && std::isnan(row[x])) ++x;
                run.x1 = x;
                fill.m_runs.push_back(run);
                parent.push_back(static_cast<std::int64_t>(parent.size()));
            }
            // Runs of the previous row sharing a column with one of this row's: one void.
            const auto end = static_cast<std::int64_t>(fill.m_runs.size());
            for (std::int64_t p = previous, c = first; p < first && c < end;) {
                const Run& above = fill.m_runs[static_cast<std::size_t>(p)];
                const Run& here = fill.m_runs[static_cast<std::size_t>(c)];
                if (above.x0 < here.x1 && here.x0 < above.x1) unite(parent, p, c);
                if (above.x1 < here.x1)
                    ++p;
                else
                    ++c;
            }
            previous = first;
        }
    }
    fill.m_rowRuns[static_cast<std::size_t>(height)] =
        static_cast<std::int64_t>(fill.m_runs.size());

    // Each void's index (in the order of its first run) and box, its rim included.
    std::vector<std::int32_t> indexOfRoot(parent.size(), -1);
    for (std::int64_t y = 0; y < height; ++y) {
        for (std::int64_t i = fill.m_rowRuns[static_cast<std::size_t>(y)];
             i < fill.m_rowRuns[static_cast<std::size_t>(y + 1)]; ++i) {
            Run& run = fill.m_runs[static_cast<std::size_t>(i)];
            const auto root = static_cast<std::size_t>(rootOf(parent, i));
            if (indexOfRoot[root] < 0) {
                indexOfRoot[root] = static_cast<std::int32_t>(fill.m_voids.size());
                Void v;
                v.x0 = run.x0;
                v.y0 = y;
                v.width = run.x1 - run.x0;  // the void's own box, for now: x1 below
                fill.m_voids.push_back(v);
            }
            run.voidIndex = indexOfRoot[root];
            Void& v = fill.m_voids[static_cast<std::size_t>(run.voidIndex)];
            const std::int64_t x1 = std::max(v.x0 + v.width, run.x1);
            v.x0 = std::min(v.x0, run.x0);
            v.width = x1 - v.x0;
            v.height = y + 1 - v.y0;
            v.samples += run.x1 - run.x0;
        }
    }
    parent.clear();
    parent.shrink_to_fit();
    for (Void& v : fill.m_voids) {
        const std::int64_t x0 = std::max<std::int64_t>(0, v.x0 - 1);
        const std::int64_t y0 = std::max<std::int64_t>(0, v.y0 - 1);
        const std::int64_t x1 = std::min(width, v.x0 + v.width + 1);
        const std::int64_t y1 = std::min(height, v.y0 + v.height + 1);
        v = Void{x0, y0, x1 - x0, y1 - y0, 1, 0, 0, {}, false, v.samples};
    }
    for (std::size_t k = 0; k < fill.m_voids.size(); ++k) {
        Void& v = fill.m_voids[k];
        if (Status solved = fill.solve(v, static_cast<std::int32_t>(k), read, beneath); !solved)
            return solved.error();
        fill.m_samples += v.samples;
        if (v.overBeneath) fill.m_samplesOverBeneath += v.samples;
    }
    return fill;
}

Status VoidFill::solve(Void& v, std::int32_t index, const ReadWindow& read,
                       const Beneath* beneath) {
    while (((v.width + v.step - 1) / v.step) * ((v.height + v.step - 1) / v.step) >
           kMaxSolveSamples)
        v.step *= 2;
    const std::int64_t step = v.step;
    v.coarseWidth = (v.width + step - 1) / step;
    v.coarseHeight = (v.height + step - 1) / step;
    const auto cells = static_cast<std::size_t>(v.coarseWidth * v.coarseHeight);
    // Per cell: the sum of its valid samples, and of their differences to the surface beneath.
    std::vector<double> sumHeight(cells, 0.0), sumDelta(cells, 0.0);
    std::vector<std::int32_t> count(cells, 0);
    bool delta = beneath != nullptr;
    // The void's own samples, in the order of its runs (full resolution only).
    std::vector<float> own;

    // Rows in chunks of whole cells, at most about kMaxSolveSamples at a time.
    const std::int64_t chunkRows =
        std::max<std::int64_t>(step, (kMaxSolveSamples / v.width) / step * step);
    std::vector<float> chunk;
    for (std::int64_t y = v.y0; y < v.y0 + v.height; y += chunkRows) {
        const std::int64_t rows = std::min(chunkRows, v.y0 + v.height - y);
        chunk.resize(static_cast<std::size_t>(rows * v.width));
        if (Status got = read(v.x0, y, v.width, rows, chunk); !got) return got;
        for (std::int64_t r = 0; r < rows; ++r) {
            const std::int64_t row = y + r;
            const std::size_t cellRow =
                static_cast<std::size_t>((row - v.y0) / step * v.coarseWidth);
            for (std::int64_t c = 0; c < v.width; ++c) {
                const float h = chunk[static_cast<std::size_t>(r * v.width + c)];
                if (std::isnan(h)) continue;
                const std::size_t cell = cellRow + static_cast<std::size_t>(c / step);
                sumHeight[cell] += h;
                ++count[cell];
                if (!delta) continue;
                const std::optional<double> under = (*beneath)(v.x0 + c, row);
                if (under)
                    sumDelta[cell] += double(h) - *under;
                else
                    delta = false;
            }
        }
    }
    // The surface beneath every sample of the void, too, or the void is filled by membrane.
    std::vector<double> under;
    if (delta) {
        for (std::int64_t row = v.y0; row < v.y0 + v.height && delta; ++row)
            for (std::int64_t i = m_rowRuns[static_cast<std::size_t>(row)];
                 i < m_rowRuns[static_cast<std::size_t>(row + 1)] && delta; ++i) {
                const Run& run = m_runs[static_cast<std::size_t>(i)];
                if (run.voidIndex != index) continue;
                for (std::int64_t x = run.x0; x < run.x1; ++x) {
                    const std::optional<double> b = (*beneath)(x, row);
                    if (!b) {
                        delta = false;
                        break;
                    }
                    if (step == 1) under.push_back(*b);
                }
            }
    }
    v.overBeneath = delta;
    std::vector<float> values(cells, 0.0f);
    std::vector<std::uint8_t> fixed(cells, 0);
    for (std::size_t i = 0; i < cells; ++i) {
        if (count[i] == 0) continue;
        fixed[i] = 1;
        values[i] = static_cast<float>((delta ? sumDelta[i] : sumHeight[i]) / count[i]);
    }
    fillMembrane(v.coarseWidth, v.coarseHeight, values, fixed);
    if (step > 1) {
        v.coarse = std::move(values);
        return {};
    }
    std::size_t k = 0;  // into under
    for (std::int64_t row = v.y0; row < v.y0 + v.height; ++row)
        for (std::int64_t i = m_rowRuns[static_cast<std::size_t>(row)];
             i < m_rowRuns[static_cast<std::size_t>(row + 1)]; ++i) {
            Run& run = m_runs[static_cast<std::size_t>(i)];
            if (run.voidIndex != index) continue;
            run.firstValue = static_cast<std::int64_t>(m_values.size());
            for (std::int64_t x = run.x0; x < run.x1; ++x) {
                const float d =
                    values[static_cast<std::size_t>((row - v.y0) * v.width + (x - v.x0))];
                m_values.push_back(delta ? static_cast<float>(under[k++] + double(d)) : d);
            }
        }
    return {};
}

float VoidFill::coarseAt(const Void& v, std::int64_t column, std::int64_t row) const {
    // Cell centres of the coarse grid in the box's samples: (i + ½) · step − ½.
    const auto axis = [&](std::int64_t at, std::int64_t origin, std::int64_t cells) {
        const double c =
            std::clamp((double(at - origin) + 0.5) / double(v.step) - 0.5, 0.0, double(cells - 1));
        const auto i0 = static_cast<std::int64_t>(c);
        return std::tuple{i0, std::min(i0 + 1, cells - 1), c - double(i0)};
    };
    const auto [x0, x1, u] = axis(column, v.x0, v.coarseWidth);
    const auto [y0, y1, t] = axis(row, v.y0, v.coarseHeight);
    const auto at = [&](std::int64_t x, std::int64_t y) {
        return double(v.coarse[static_cast<std::size_t>(y * v.coarseWidth + x)]);
    };
    const double top = (1.0 - u) * at(x0, y0) + u * at(x1, y0);
    const double bottom = (1.0 - u) * at(x0, y1) + u * at(x1, y1);
    return static_cast<float>((1.0 - t) * top + t * bottom);
}

const VoidFill::Run* VoidFill::runAt(std::int64_t column, std::int64_t row) const {
    if (row < 0 || row + 1 >= std::ssize(m_rowRuns)) return nullptr;
    const auto first = m_runs.begin() + m_rowRuns[static_cast<std::size_t>(row)];
    const auto last = m_runs.begin() + m_rowRuns[static_cast<std::size_t>(row + 1)];
    auto it = std::upper_bound(first, last, column,
                               [](std::int64_t c, const Run& run) { return c < run.x0; });
    if (it == first) return nullptr;
    --it;
    return column < it->x1 ? &*it : nullptr;
}

float VoidFill::at(std::int64_t column, std::int64_t row, const Beneath* beneath) const {
    const Run* run = runAt(column, row);
    TERRAIN_ASSERT(run != nullptr, "VoidFill::at of a sample that is not no-data");
    if (run->firstValue >= 0)
        return m_values[static_cast<std::size_t>(run->firstValue + column - run->x0)];
    const Void& v = m_voids[static_cast<std::size_t>(run->voidIndex)];
    const float d = coarseAt(v, column, row);
    if (!v.overBeneath) return d;
    TERRAIN_ASSERT(beneath != nullptr, "a void filled over the source beneath needs it");
    const std::optional<double> under = (*beneath)(column, row);
    TERRAIN_ASSERT(under.has_value());
    return static_cast<float>(*under + double(d));
}

}  // namespace terrain::io::detail
