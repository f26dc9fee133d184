#include "GeographicGrid.h"

#include "BuildBudget.h"

#include "terrain/globe/Wgs84.h"
#include "terrain/pyramid/PatchErrors.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <span>

namespace terrain::io {

namespace {

// Integer pixel and weight of a fractional centre coordinate, clamped to [0, count − 1].
struct Axis {
    std::int64_t first = 0, second = 0;
    double weight = 0.0;  // of `second`
};

Axis clampedAxis(double centre, std::int64_t count) {
    if (centre <= 0.0) return {0, 0, 0.0};
    const double last = double(count - 1);
    if (centre >= last) return {count - 1, count - 1, 0.0};
    const auto first = static_cast<std::int64_t>(centre);
    return {first, first + 1, centre - double(first)};
}

}  // namespace

Result<GeographicGrid> GeographicGrid::describe(const DemInfo& dem) {
    const Georeference& g = dem.georeference;
    if (g.crsKind != CrsKind::Geographic)
        return Error{
            fmt::format("{}: a globe pyramid needs a geographic (longitude/latitude) "
                        "source, and this one is {}",
                        dem.path, crsKindName(g.crsKind))};
    // A global grid may repeat its first column(s) after 360° (ETOPO's −180 and +180): those
    // columns are the same longitudes, and the grid wraps after the first 360°.
    const double span = double(dem.width) * g.pixelSizeX;
    const double tolerance = 1e-3 * g.pixelSizeX;
    const auto repeated =
        static_cast<std::int64_t>(std::floor((span - 360.0 + tolerance) / g.pixelSizeX));
    // A grid whose first or last row is centred on a pole (grid-registered, like the built-in
    // planet's) reaches half a pixel beyond it.
    const double poleReach = 0.5 * g.pixelSizeY + tolerance;
    if (g.originY > 90.0 + poleReach ||
        g.originY - double(dem.height) * g.pixelSizeY < -90.0 - poleReach || repeated > 1 ||
        (repeated == 1 && std::abs(span - g.pixelSizeX - 360.0) > tolerance) ||
        (repeated == 0 && span > 360.0 + tolerance))
        return Error{fmt::format(
            "{}: the geographic extent (west {}, north {}, {} × {} pixels of "
            "{}° × {}°) is not on the globe",
            dem.path, g.originX, g.originY, dem.width, dem.height, g.pixelSizeX, g.pixelSizeY)};

    GeographicGrid grid;
    grid.m_width = dem.width;
    grid.m_height = dem.height;
    grid.m_west = g.originX;
    grid.m_north = g.originY;
    grid.m_pixelLon = g.pixelSizeX;
    grid.m_pixelLat = g.pixelSizeY;
    grid.m_wraps = span >= 360.0 - tolerance;
    grid.m_wrapColumns = dem.width - std::max<std::int64_t>(repeated, 0);
    // A pole beyond the edge row's centres of a grid around the globe (not one whose edge
    // row is centred on it: that row is the pole's own samples).
    if (grid.m_wraps) {
        const double north = (g.originY - 90.0) / g.pixelSizeY - 0.5;
        const double south = (g.originY + 90.0) / g.pixelSizeY - 0.5;
        grid.m_poles[0] = {north < -1e-6 && g.originY >= 90.0 - 1e-6, north, 0.0f, false};
        grid.m_poles[1] = {south > double(dem.height - 1) + 1e-6 &&
                               g.originY - double(dem.height) * g.pixelSizeY <= -90.0 + 1e-6,
                           south, 0.0f, false};
    }
    return grid;
}

std::optional<std::int64_t> GeographicGrid::poleRow(int side) const {
    if (!m_poles[static_cast<std::size_t>(side)].present) return std::nullopt;
    return side == 0 ? 0 : m_height - 1;
}

void GeographicGrid::setPole(int side, std::span<const float> edgeRow,
                             std::span<const std::uint8_t> valid) {
    Pole& pole = m_poles[static_cast<std::size_t>(side)];
    // In double, column by column: a region build reading the row itself sums it alike.
    double sum = 0.0;
    std::int64_t count = 0;
    bool allValid = true;
    for (std::size_t i = 0; i < static_cast<std::size_t>(m_wrapColumns); ++i) {
        allValid = allValid && valid[i] != 0;
        if (std::isnan(edgeRow[i])) continue;  // a void not filled yet (read, before fillVoids)
        sum += double(edgeRow[i]);
        ++count;
    }
    pole.height = count > 0 ? static_cast<float>(sum / double(count)) : 0.0f;
    pole.valid = allValid && count > 0;
}

void GeographicGrid::setPolesFromSamples() {
    for (int side = 0; side < 2; ++side) {
        const std::optional<std::int64_t> row = poleRow(side);
        if (!row) continue;
        const std::size_t first = index(0, *row);
        setPole(side, std::span<const float>(m_heights).subspan(first, std::size_t(m_width)),
                std::span<const std::uint8_t>(m_valid).subspan(first, std::size_t(m_width)));
    }
}

std::optional<std::pair<int, double>> GeographicGrid::inPoleFan(double centre) const {
    if (centre < 0.0 && m_poles[0].present)
        return std::pair{0, std::min(1.0, centre / m_poles[0].centre)};
    const double last = double(m_height - 1);
    if (centre > last && m_poles[1].present)
        return std::pair{1, std::min(1.0, (centre - last) / (m_poles[1].centre - last))};
    return std::nullopt;
}

Result<GeographicGrid> GeographicGrid::read(DemReader& reader, std::uint64_t memoryBudgetBytes,
                                            unsigned shares) {
    const DemInfo& dem = reader.info();
    Result<GeographicGrid> described = describe(dem);
    if (!described) return described.error();
    const auto bytes = static_cast<std::uint64_t>(double(dem.width) * double(dem.height) * 5.0);
    if (Status fits = detail::checkMemoryBudget(
            dem.path, fmt::format("holding its {} × {} samples whole", dem.width, dem.height),
            bytes * shares, memoryBudgetBytes,
            "raise --memory (a globe build holds its sources in half of it, shared among them)");
        !fits)
        return fits.error();
    GeographicGrid grid = std::move(described).value();
    const auto samples = static_cast<std::size_t>(dem.width * dem.height);
    grid.m_heights.resize(samples);
    grid.m_valid.resize(samples);
    // Row bands keep the reader's calls large without a second copy of the raster.
    const std::int64_t bandRows = std::max<std::int64_t>(1, (std::int64_t{1} << 22) / dem.width);
    double minHeight = std::numeric_limits<double>::infinity();
    double maxHeight = -minHeight;
    for (std::int64_t row = 0; row < dem.height; row += bandRows) {
        const std::int64_t rows = std::min(bandRows, dem.height - row);
        std::span<float> band(grid.m_heights.data() + row * dem.width,
                              static_cast<std::size_t>(rows * dem.width));
        if (Status read = reader.readWindow(0, row, dem.width, rows, band); !read)
            return read.error();
        for (std::int64_t r = 0; r < rows; ++r) {
            const auto offset = static_cast<std::size_t>((row + r) * dem.width);
            for (std::size_t i = offset; i < offset + static_cast<std::size_t>(dem.width); ++i) {
                grid.m_valid[i] = std::isnan(grid.m_heights[i]) ? 0 : 1;
                if (!grid.m_valid[i]) continue;
                ++grid.m_validSamples;
                minHeight = std::min(minHeight, double(grid.m_heights[i]));
                maxHeight = std::max(maxHeight, double(grid.m_heights[i]));
            }
        }
    }
    grid.m_minHeight = grid.m_validSamples > 0 ? minHeight : 0.0;
    grid.m_maxHeight = grid.m_validSamples > 0 ? maxHeight : 0.0;
    grid.setPolesFromSamples();
    return grid;
}

Status GeographicGrid::fillVoids(const detail::VoidFill::Beneath* beneath) {
    if (m_validSamples == m_width * m_height) return {};
    const detail::VoidFill::ReadWindow read = [this](std::int64_t x0, std::int64_t y0,
                                                     std::int64_t width, std::int64_t rows,
                                                     std::span<float> out) -> Status {
        for (std::int64_t r = 0; r < rows; ++r)
            std::copy_n(m_heights.begin() + static_cast<std::ptrdiff_t>(index(x0, y0 + r)), width,
                        out.begin() + static_cast<std::ptrdiff_t>(r * width));
        return {};
    };
    Result<detail::VoidFill> found = detail::VoidFill::find(m_width, m_height, read, beneath);
    if (!found) return found.error();
    const detail::VoidFill& voids = found.value();
    for (std::int64_t row = 0; row < m_height; ++row)
        for (std::int64_t col = 0; col < m_width; ++col)
            if (!m_valid[index(col, row)]) m_heights[index(col, row)] = voids.at(col, row, beneath);
    m_filledSamples = voids.samples();
    m_filledOverBeneath = voids.samplesOverBeneath();
    setPolesFromSamples();  // of the filled row
    return {};
}

std::optional<GeographicGrid::Location> GeographicGrid::locate(double latitudeDeg,
                                                               double longitudeDeg) const {
    // Within one pixel beyond the extent the edge pixels are extended (not valid, not
    // inside), tapered to the bare ellipsoid (edgeTaper): the face grid is at least as fine
    // as a pixel, so the drop happens outside every cell that holds a source sample, and
    // Err(P) measures the source, not the cliff at its border.
    const double y = m_north - latitudeDeg;
    const double height = double(m_height) * m_pixelLat;
    if (y < -m_pixelLat || y > height + m_pixelLat) return std::nullopt;
    double x = std::fmod(longitudeDeg - m_west, 360.0);
    if (x < 0.0) x += 360.0;
    const double width = double(m_width) * m_pixelLon;
    if (!m_wraps && x > width + m_pixelLon) {
        if (x < 360.0 - m_pixelLon) return std::nullopt;
        x -= 360.0;  // just west of the grid
    }
    Location where;
    where.inside = y >= 0.0 && y <= height && (m_wraps || (x >= 0.0 && x <= width));
    where.taper = edgeTaper(y, x);
    const double rowCentre = y / m_pixelLat - 0.5;
    Axis rows = clampedAxis(rowCentre, m_height);
    if (const auto fan = inPoleFan(rowCentre)) {
        // The edge row twice, one of them standing for the pole (interpolate).
        const auto [side, weight] = *fan;
        const Pole& pole = m_poles[static_cast<std::size_t>(side)];
        where.poleRow = side == 0 ? 0 : 1;
        where.poleHeight = pole.height;
        where.poleValid = pole.valid;
        rows.weight = side == 0 ? 1.0 - weight : weight;
    }
    Axis columns;
    if (m_wraps) {
        // Between the last and the first column across the seam of a 360° grid.
        const double centre = x / m_pixelLon - 0.5;
        const double first = std::floor(centre);
        columns.weight = centre - first;
        columns.first =
            (static_cast<std::int64_t>(first) % m_wrapColumns + m_wrapColumns) % m_wrapColumns;
        columns.second = (columns.first + 1) % m_wrapColumns;
    } else {
        columns = clampedAxis(x / m_pixelLon - 0.5, m_width);
    }
    where.rows[0] = rows.first;
    where.rows[1] = rows.second;
    where.rowWeight = rows.weight;
    where.columns[0] = columns.first;
    where.columns[1] = columns.second;
    where.columnWeight = columns.weight;
    return where;
}

double GeographicGrid::edgeTaper(double y, double x) const {
    // Linear in the distance beyond each edge, so the face grid's triangles draw the drop
    // along the extent's own outline wherever its vertices fall: a step to 0 at a fixed
    // distance would draw a staircase of cells where the grid runs askew to the edge.
    const double height = double(m_height) * m_pixelLat;
    const double beyondRows = std::max(-y, y - height) / m_pixelLat;
    double taper = 1.0 - std::clamp(beyondRows, 0.0, 1.0);
    if (!m_wraps) {
        const double width = double(m_width) * m_pixelLon;
        const double beyondColumns = std::max(-x, x - width) / m_pixelLon;
        taper *= 1.0 - std::clamp(beyondColumns, 0.0, 1.0);
    }
    return taper;
}

std::vector<std::pair<double, double>> GeographicGrid::taperPlaces() const {
    std::vector<std::pair<double, double>> places;
    const std::array<bool, kSeamEdges> present = edges();
    const auto has = [&](SeamEdge e) { return present[static_cast<std::size_t>(e)]; };
    // Pixel-centre coordinates of the edge (d = 0) and a pixel beyond it (d = 1).
    for (const double beyond : {0.0, 1.0}) {
        for (std::int64_t col = -1; col <= m_width; ++col) {
            const double longitude = longitudeAt(double(col));
            if (has(SeamEdge::North)) places.emplace_back(latitudeAt(-0.5 - beyond), longitude);
            if (has(SeamEdge::South))
                places.emplace_back(latitudeAt(double(m_height) - 0.5 + beyond), longitude);
        }
        for (std::int64_t row = -1; row <= m_height; ++row) {
            const double latitude = latitudeAt(double(row));
            if (has(SeamEdge::West)) places.emplace_back(latitude, longitudeAt(-0.5 - beyond));
            if (has(SeamEdge::East))
                places.emplace_back(latitude, longitudeAt(double(m_width) - 0.5 + beyond));
        }
    }
    places.erase(std::remove_if(places.begin(), places.end(),
                                [](const auto& p) { return std::abs(p.first) > 90.0; }),
                 places.end());
    return places;
}

GeographicGrid::Resampled GeographicGrid::interpolate(const Location& where,
                                                      const float corner[2][2],
                                                      const bool valid[2][2]) {
    Resampled out;
    out.inside = where.inside;
    out.valid = where.inside;
    out.covered = true;
    if (where.poleRow >= 0) {
        const float withPole[2][2] = {{where.poleRow == 0 ? where.poleHeight : corner[0][0],
                                       where.poleRow == 0 ? where.poleHeight : corner[0][1]},
                                      {where.poleRow == 1 ? where.poleHeight : corner[1][0],
                                       where.poleRow == 1 ? where.poleHeight : corner[1][1]}};
        const bool validWithPole[2][2] = {{where.poleRow == 0 ? where.poleValid : valid[0][0],
                                           where.poleRow == 0 ? where.poleValid : valid[0][1]},
                                          {where.poleRow == 1 ? where.poleValid : valid[1][0],
                                           where.poleRow == 1 ? where.poleValid : valid[1][1]}};
        Location onRows = where;
        onRows.poleRow = -1;
        return interpolate(onRows, withPole, validWithPole);
    }
    // On the source's own triangles (each cell split along its north-west – south-east
    // diagonal), not bilinear: between its pixel centres the DEM is the mesh the reference
    // measures against, and a bilinear patch departs from it by a quarter of the cell's twist
    // (hundreds of metres in a 37 km cell of a global grid).
    for (int r = 0; r < 2; ++r) {
        for (int c = 0; c < 2; ++c) {
            const double w = (r == 0 ? 1.0 - where.rowWeight : where.rowWeight) *
                             (c == 0 ? 1.0 - where.columnWeight : where.columnWeight);
            if (w > 0.0) out.valid = out.valid && valid[r][c];
        }
    }
    out.height = static_cast<float>(
        where.taper * cellSurfaceHeights(corner[0][0], corner[0][1], corner[1][0], corner[1][1],
                                         where.columnWeight, where.rowWeight)
                          .first);
    return out;
}

GeographicGrid::Resampled GeographicGrid::at(double latitudeDeg, double longitudeDeg) const {
    const std::optional<Location> where = locate(latitudeDeg, longitudeDeg);
    if (!where) return {};
    float corner[2][2] = {};
    bool valid[2][2] = {};
    for (int r = 0; r < 2; ++r) {
        for (int c = 0; c < 2; ++c) {
            const std::size_t i = index(where->columns[c], where->rows[r]);
            corner[r][c] = m_heights[i];
            valid[r][c] = m_valid[i] != 0;
        }
    }
    return interpolate(*where, corner, valid);
}

std::optional<GeographicGrid::Cell> GeographicGrid::cellAt(double latitudeDeg,
                                                           double longitudeDeg) const {
    const double y = m_north - latitudeDeg;
    if (y < -m_pixelLat || y > double(m_height) * m_pixelLat + m_pixelLat) return std::nullopt;
    double x = std::fmod(longitudeDeg - m_west, 360.0);
    if (x < 0.0) x += 360.0;
    const double width = double(m_width) * m_pixelLon;
    if (!m_wraps && x > width + m_pixelLon) {
        if (x < 360.0 - m_pixelLon) return std::nullopt;
        x -= 360.0;
    }
    const double row = std::clamp(y / m_pixelLat - 0.5, 0.0, double(m_height - 1));
    const auto row0 =
        std::min(static_cast<std::int64_t>(row), std::max<std::int64_t>(m_height - 2, 0));
    const std::int64_t row1 = std::min(row0 + 1, m_height - 1);
    std::int64_t col0 = 0, col1 = 0;
    double u = 0.0;
    if (m_wraps) {
        const double centre = x / m_pixelLon - 0.5;
        const double first = std::floor(centre);
        u = centre - first;
        col0 = (static_cast<std::int64_t>(first) % m_wrapColumns + m_wrapColumns) % m_wrapColumns;
        col1 = (col0 + 1) % m_wrapColumns;
    } else {
        const double col = std::clamp(x / m_pixelLon - 0.5, 0.0, double(m_width - 1));
        col0 = std::min(static_cast<std::int64_t>(col), std::max<std::int64_t>(m_width - 2, 0));
        col1 = std::min(col0 + 1, m_width - 1);
        u = col1 > col0 ? col - double(col0) : 0.0;
    }
    Cell cell;
    cell.taper = edgeTaper(y, x);
    cell.u = std::clamp(u, 0.0, 1.0);
    cell.longitude[0] = longitudeOf(col0);
    cell.longitude[1] = longitudeOf(col1);
    if (const auto fan = inPoleFan(y / m_pixelLat - 0.5)) {
        // The cell between the edge row and the pole (locate, interpolate).
        const auto [side, weight] = *fan;
        const double pole = m_poles[static_cast<std::size_t>(side)].height;
        const std::int64_t edge = side == 0 ? 0 : m_height - 1;
        const double west = m_heights[index(col0, edge)], east = m_heights[index(col1, edge)];
        if (side == 0) {
            cell.a = cell.b = pole;
            cell.c = west;
            cell.d = east;
            cell.latitude[0] = 90.0;
            cell.latitude[1] = latitudeOf(edge);
            cell.v = 1.0 - weight;
        } else {
            cell.a = west;
            cell.b = east;
            cell.c = cell.d = pole;
            cell.latitude[0] = latitudeOf(edge);
            cell.latitude[1] = -90.0;
            cell.v = weight;
        }
        return cell;
    }
    cell.latitude[0] = latitudeOf(row0);
    cell.latitude[1] = latitudeOf(row1);
    cell.a = m_heights[index(col0, row0)];
    cell.b = m_heights[index(col1, row0)];
    cell.c = m_heights[index(col0, row1)];
    cell.d = m_heights[index(col1, row1)];
    cell.v = row1 > row0 ? std::clamp(row - double(row0), 0.0, 1.0) : 0.0;
    return cell;
}

std::pair<double, double> GeographicGrid::pixelPosition(double latitudeDeg,
                                                        double longitudeDeg) const {
    double x = std::fmod(longitudeDeg - m_west, 360.0);
    if (x < 0.0) x += 360.0;
    // A point west of the grid is nearer its west edge across the antimeridian than its east.
    const double width = double(m_width) * m_pixelLon;
    if (!m_wraps && x > width && x - width > 360.0 - x) x -= 360.0;
    return {x / m_pixelLon, (m_north - latitudeDeg) / m_pixelLat};
}

std::array<bool, kSeamEdges> GeographicGrid::edges() const {
    std::array<bool, kSeamEdges> edges{};
    edges[static_cast<std::size_t>(SeamEdge::West)] = !m_wraps;
    edges[static_cast<std::size_t>(SeamEdge::East)] = !m_wraps;
    edges[static_cast<std::size_t>(SeamEdge::North)] = m_north < 90.0 - 1e-6;
    edges[static_cast<std::size_t>(SeamEdge::South)] = southDeg() > -90.0 + 1e-6;
    return edges;
}

double GeographicGrid::eastWestMetres(double latitudeDeg) const {
    // The parallel's radius: the prime vertical's, N = a / √(1 − e² sin² φ), times cos φ.
    const double s = std::sin(latitudeDeg * kDegree);
    const double n = globe::Wgs84::kEquatorialRadius /
                     std::sqrt(1.0 - globe::Wgs84::kEccentricitySquared * s * s);
    return m_pixelLon * kDegree * n * std::cos(latitudeDeg * kDegree);
}

double GeographicGrid::northSouthMetres(double latitudeDeg) const {
    // The meridian's radius of curvature, M = a (1 − e²) / (1 − e² sin² φ)^1.5.
    const double s = std::sin(latitudeDeg * kDegree);
    const double e2 = globe::Wgs84::kEccentricitySquared;
    const double m = globe::Wgs84::kEquatorialRadius * (1.0 - e2) / std::pow(1.0 - e2 * s * s, 1.5);
    return m_pixelLat * kDegree * m;
}

double GeographicGrid::finestSpacingMetres() const {
    return geographicFinestSpacingMetres(southDeg(), m_north, m_pixelLon, m_pixelLat);
}

double geographicFinestSpacingMetres(double southDeg, double northDeg, double pixelLonDeg,
                                     double pixelLatDeg) {
    const double closestToEquator = (southDeg <= 0.0 && northDeg >= 0.0)
                                        ? 0.0
                                        : std::min(std::abs(southDeg), std::abs(northDeg));
    // The meridian's radius of curvature is smallest (b²/a) at the equator.
    const double alongMeridian = pixelLatDeg * kDegree * globe::Wgs84::kMinCurvatureRadius;
    const double alongParallel = pixelLonDeg * globe::Wgs84::kEquatorialRadius * kDegree *
                                 std::cos(closestToEquator * kDegree);
    return std::min(alongMeridian, alongParallel);
}

}  // namespace terrain::io
