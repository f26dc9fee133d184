// FakeImageryImage: an image of `colour(x, y)` laid on a planar pyramid's finest samples, for
// the imagery builder's tests: pixel (x, y) covers finest samples [x0 + x · size, …) (sample
// c's centre at c + 0.5 in this frame, as the image's pixel centres are).
#pragma once

#include "terrain/build/ImageryLayerBuilder.h"
#include "terrain/source/ImageryImage.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>

namespace terrain::test {

using ImageColour = std::function<std::array<std::uint8_t, 4>(std::int64_t, std::int64_t)>;

// Pixel (x, y) covers finest samples [x0 + x · size, …): a picture laid on the DEM's samples
// (sample c's centre at c + 0.5 in this frame, as the image's pixel centres are).
class FakeImageryImage final : public io::ImageryImage {
public:
    FakeImageryImage(std::int64_t w, std::int64_t h, double x0, double y0, double size,
                     ImageColour colour)
        : m_w(w), m_h(h), m_x0(x0), m_y0(y0), m_size(size), m_colour(std::move(colour)) {}
    const std::string& name() const override { return m_name; }
    std::int64_t width() const override { return m_w; }
    std::int64_t height() const override { return m_h; }
    bool wrapsColumns() const override { return false; }
    void toPixels(std::span<double> xs, std::span<double> ys) override {
        for (std::size_t i = 0; i < xs.size(); ++i) {
            xs[i] = (xs[i] + 0.5 - m_x0) / m_size;
            ys[i] = (ys[i] + 0.5 - m_y0) / m_size;
        }
    }
    std::array<double, 2> toTerrain(double x, double y) override {
        return {x * m_size + m_x0 - 0.5, y * m_size + m_y0 - 0.5};
    }
    Status readBlocks(std::int64_t bx0, std::int64_t by0, int w, int h, int k,
                      std::span<std::uint8_t> rgba) override {
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) {
                double sum[4] = {0, 0, 0, 0};
                int n = 0;
                for (std::int64_t y = (by0 + j) << k; y < std::min(m_h, (by0 + j + 1) << k); ++y)
                    for (std::int64_t x = (bx0 + i) << k; x < std::min(m_w, (bx0 + i + 1) << k);
                         ++x, ++n) {
                        const auto c = m_colour(x, y);
                        for (int ch = 0; ch < 4; ++ch) sum[ch] += c[static_cast<std::size_t>(ch)];
                    }
                for (int ch = 0; ch < 4; ++ch)
                    rgba[static_cast<std::size_t>((j * w + i) * 4 + ch)] =
                        static_cast<std::uint8_t>(std::lround(sum[ch] / std::max(n, 1)));
            }
        return {};
    }

private:
    std::string m_name{"fake.tif"};
    std::int64_t m_w, m_h;
    double m_x0, m_y0, m_size;
    ImageColour m_colour;
};

inline io::ImageryImageOpener fakeImageryOpener(std::int64_t w, std::int64_t h, double x0,
                                                double y0, double size, ImageColour colour) {
    return [=]() -> Result<std::unique_ptr<io::ImageryImage>> {
        return std::unique_ptr<io::ImageryImage>(new FakeImageryImage(w, h, x0, y0, size, colour));
    };
}

}  // namespace terrain::test
