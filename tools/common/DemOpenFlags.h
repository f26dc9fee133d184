// The command-line flags that describe a DEM the file itself does not (vertical units,
// georeference, no-data), shared by every program that opens a DEM.
#pragma once

#include "terrain/dem/OpenDem.h"
#include "terrain/source/DemReader.h"

#include <CLI/CLI.hpp>

#include <vector>

namespace terrain::tools {

/// Adds --vertical-scale, --vertical-offset, --spacing, --origin X,Y, --epsg and --nodata.
/// Call applyOrigin() after parsing.
class DemOpenFlags {
public:
    void addTo(CLI::App& app) {
        app.add_option("--vertical-scale", m_options.verticalScale,
                       "Metres per raw unit (e.g. 0.1 for the Puget Sound PNGs)");
        app.add_option("--vertical-offset", m_options.verticalOffset, "Metres added after scaling");
        app.add_option("--spacing", m_options.pixelSize,
                       "Sample spacing in map units (DEMs without georeference)");
        app.add_option("--origin", m_origin, "Map X,Y of the north-west corner (no georeference)")
            ->expected(2)
            ->delimiter(',');
        app.add_option("--epsg", m_options.epsg, "EPSG code of the CRS (no georeference)");
        app.add_option("--nodata", m_options.noDataValue,
                       "Raw no-data value (overrides the file's)");
        app.add_option("-b,--band", m_options.band,
                       "Raster band to read heights from, 1-based as GDAL numbers them "
                       "(default 1, with a warning when the input has several)");
        // No range check here: opening the DEM refuses a band it lacks, 0 and negative
        // ones included, naming the file and its bands (CLI11's check printed its own
        // range, 0 to DBL_MAX in full, and exited 105).
    }

    const io::DemOpenOptions& options() {
        if (m_origin.size() == 2) {
            m_options.originX = m_origin[0];
            m_options.originY = m_origin[1];
        }
        return m_options;
    }

private:
    io::DemOpenOptions m_options;
    std::vector<double> m_origin;
};

}  // namespace terrain::tools
