// GeographicGrid: a geographic (longitude/latitude) source DEM held in memory, resampled at
// any latitude and longitude for the globe builder. No-data samples are filled (fillVoids:
// over the sources beneath, or by the membrane, VoidFill.h; docs/pyramid-format.md,
// "No-data") and remembered as invalid, so a void is drawn as its fill, never as a hole to
// the ellipsoid. Samples are pixel areas
// (Georeference.h): sample (col, row) is the value at the pixel's centre.
#pragma once

#include "VoidFill.h"
#include "terrain/base/Result.h"
#include "terrain/build/SeamBand.h"
#include "terrain/source/DemReader.h"

#include <array>
#include <cstdint>
#include <numbers>
#include <optional>
#include <span>
#include <utility>
#include <vector>

namespace terrain::io {

/// Radians per degree.
inline constexpr double kDegree = std::numbers::pi / 180.0;

class GeographicGrid {
public:
    /// Reads the whole source, its no-data samples NaN until fillVoids. Errors: not
    /// geographic, more than 1/`shares` of `memoryBudgetBytes` to hold (the budget is shared
    /// among sources and the patches).
    static Result<GeographicGrid> read(DemReader& reader, std::uint64_t memoryBudgetBytes,
                                       unsigned shares);
    /// The source's grid without its samples (a region build reads them block by block,
    /// GeographicBlocks.h): every geometric accessor works, heightAt, validAt, at and cellAt
    /// do not. Errors: not geographic, not on the globe.
    static Result<GeographicGrid> describe(const DemInfo& dem);

    struct Resampled {
        float height = 0.0f;   ///< metres; tapered to 0 over the pixel beyond the source
        bool inside = false;   ///< within the source's extent (pixel areas)
        bool valid = false;    ///< inside, and every sample it interpolates is valid
        bool covered = false;  ///< inside, or within the one pixel its edge pixels extend to
    };
    /// On the triangles between the pixel centres around the point (each cell split along its
    /// north-west – south-east diagonal), clamped to the edge pixels up to one pixel beyond the
    /// extent and tapered there linearly to 0 (the bare ellipsoid) at that pixel's far side;
    /// across the antimeridian when the grid spans 360°.
    Resampled at(double latitudeDeg, double longitudeDeg) const;

    /// Where `at` reads: the two rows and two columns of pixel centres around the point (the
    /// same one twice where clamped to an edge) and the point's weights between them.
    struct Location {
        std::int64_t rows[2] = {0, 0};
        std::int64_t columns[2] = {0, 0};
        double rowWeight = 0.0, columnWeight = 0.0;  ///< of rows[1] and columns[1]
        bool inside = false;
        double taper = 1.0;  ///< what the height is multiplied by (edgeTaper)
        /// Between the edge row and a pole the grid reaches (Pole): which of the two rows is
        /// the pole (-1 none), its height and validity in place of that row's samples.
        int poleRow = -1;
        float poleHeight = 0.0f;
        bool poleValid = false;
    };
    /// Nothing more than a pixel beyond the extent (where `at` gives height 0, not covered).
    std::optional<Location> locate(double latitudeDeg, double longitudeDeg) const;
    /// `at`'s value from the location's corner samples: [r][c] of rows[r], columns[c] (the
    /// pole's in place of row `poleRow`'s).
    static Resampled interpolate(const Location& where, const float corner[2][2],
                                 const bool valid[2][2]);

    /// The cell of pixel centres around a point inside (or within a pixel of) the extent:
    /// its corner heights (filled values) a north-west, b north-east, c south-west, d
    /// south-east, and the point's position (u east, v south) in it; nothing further out.
    struct Cell {
        double a = 0.0, b = 0.0, c = 0.0, d = 0.0;
        double u = 0.0, v = 0.0;
        double taper = 1.0;  ///< beyond the extent, what the surface is multiplied by
        double latitude[2] = {0.0, 0.0};   ///< of the cell's rows (north, south)
        double longitude[2] = {0.0, 0.0};  ///< of its columns (west, east)
    };
    /// Where a point lies on the grid, pixels east of its west edge and south of its north
    /// edge (pixel areas: 0 on the edge; across the antimeridian for a point just west of
    /// the grid): what SeamBand::weight takes.
    std::pair<double, double> pixelPosition(double latitudeDeg, double longitudeDeg) const;
    /// Which edges of the extent are edges (SeamEdge's order): a pole is a point of a grid
    /// reaching it, and a grid wrapping the globe has no east or west edge.
    std::array<bool, kSeamEdges> edges() const;
    /// A pixel's ground size at a latitude, metres: east–west (along the parallel) and
    /// north–south (along the meridian), on the ellipsoid.
    double eastWestMetres(double latitudeDeg) const;
    double northSouthMetres(double latitudeDeg) const;
    std::optional<Cell> cellAt(double latitudeDeg, double longitudeDeg) const;

    /// A grid around the whole globe whose edge row lies short of a pole (ETOPO's last row at
    /// 89.83° S) holds one height there: the mean of that row's filled samples. Between the
    /// row and the pole its surface is a fan, each cell of the row meeting the pole in one
    /// point, so the surface is one surface there (clamping the rows, as elsewhere beyond
    /// the edge, would meet the pole at every height of the row at once, which no drawn
    /// surface can). `side` 0 north, 1 south; the edge row, if the grid has that pole.
    std::optional<std::int64_t> poleRow(int side) const;
    /// Sets the pole's height from its edge row's filled samples and validity (the first
    /// wrapping columns of them: the longitudes before they repeat), as `read` and
    /// `fillVoids` do from the grid they hold; a region build reads the row itself.
    void setPole(int side, std::span<const float> edgeRow, std::span<const std::uint8_t> valid);
    /// The longitudes of one turn: the columns before they repeat (the width if not wrapping).
    std::int64_t wrapColumns() const { return m_wrapColumns; }
    /// 1 within the extent, falling linearly to 0 over the pixel beyond each edge (a product
    /// at a corner); y and x in degrees south of the north edge and east of the west edge.
    double edgeTaper(double y, double x) const;
    /// Where the taper runs, as (latitude, longitude): along each edge of the extent, one
    /// place per pixel (and past the corners) on the edge and one a pixel beyond it. Between
    /// them the surface is linear across the edge, so Err(P) measured at these places holds a
    /// coarse patch's ramp from the edge down to the bare ellipsoid.
    std::vector<std::pair<double, double>> taperPlaces() const;

    std::int64_t width() const { return m_width; }
    std::int64_t height() const { return m_height; }
    /// Latitude and longitude of pixel (col, row)'s centre.
    double latitudeOf(std::int64_t row) const { return latitudeAt(double(row)); }
    double longitudeOf(std::int64_t col) const { return longitudeAt(double(col)); }
    /// Latitude and longitude of a place between pixel centres: y and x in pixels, the
    /// centre of pixel (0, 0) at (0, 0).
    double latitudeAt(double y) const { return m_north - (y + 0.5) * m_pixelLat; }
    double longitudeAt(double x) const { return m_west + (x + 0.5) * m_pixelLon; }
    float heightAt(std::int64_t col, std::int64_t row) const { return m_heights[index(col, row)]; }
    bool validAt(std::int64_t col, std::int64_t row) const { return m_valid[index(col, row)] != 0; }

    /// The smallest distance between neighbouring samples, metres: along a meridian, or along
    /// the parallel closest to the equator within the grid.
    double finestSpacingMetres() const;
    double westDeg() const { return m_west; }
    double northDeg() const { return m_north; }
    double eastDeg() const { return m_west + double(m_width) * m_pixelLon; }
    double southDeg() const { return m_north - double(m_height) * m_pixelLat; }
    bool wrapsLongitude() const { return m_wraps; }
    /// A pixel's size, degrees of latitude and of longitude.
    double pixelLatDeg() const { return m_pixelLat; }
    double pixelLonDeg() const { return m_pixelLon; }

    /// Fills the voids of a grid `read` (VoidFill::find): over `beneath` (the sources under
    /// this one, at this grid's samples) where it covers a void, else by the membrane.
    Status fillVoids(const detail::VoidFill::Beneath* beneath = nullptr);
    /// No-data samples fillVoids filled; those of them over the sources beneath.
    std::int64_t filledSamples() const { return m_filledSamples; }
    std::int64_t filledOverBeneath() const { return m_filledOverBeneath; }

    std::int64_t validSamples() const { return m_validSamples; }
    double minHeight() const { return m_minHeight; }  ///< over valid samples (0 if none)
    double maxHeight() const { return m_maxHeight; }

private:
    std::size_t index(std::int64_t col, std::int64_t row) const {
        return static_cast<std::size_t>(row * m_width + col);
    }
    void setPolesFromSamples();
    // Where a point (centre: its row coordinate, pixel centres at whole numbers) lies in a
    // pole's fan: the pole's side and its weight (0 at the edge row, 1 at the pole).
    std::optional<std::pair<int, double>> inPoleFan(double centre) const;

    struct Pole {
        bool present = false;
        double centre = 0.0;  // the pole's row coordinate
        float height = 0.0f;
        bool valid = false;
    };

    std::int64_t m_width = 0, m_height = 0;
    double m_west = 0.0, m_north = 0.0, m_pixelLon = 1.0, m_pixelLat = 1.0;
    bool m_wraps = false;
    std::int64_t m_wrapColumns = 0;  // columns before the longitudes repeat (wrapping grids)
    std::array<Pole, 2> m_poles;     // north, south
    std::vector<float> m_heights;
    std::vector<std::uint8_t> m_valid;
    std::int64_t m_validSamples = 0;
    std::int64_t m_filledSamples = 0, m_filledOverBeneath = 0;
    double m_minHeight = 0.0, m_maxHeight = 0.0;
};

/// GeographicGrid::finestSpacingMetres of a grid of pixelLonDeg × pixelLatDeg cells between
/// southDeg and northDeg (its edges): from a source's header, before it is read.
double geographicFinestSpacingMetres(double southDeg, double northDeg, double pixelLonDeg,
                                     double pixelLatDeg);

}  // namespace terrain::io
