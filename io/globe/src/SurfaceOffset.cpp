#include "terrain/globe/SurfaceOffset.h"

#include "terrain/globe/Wgs84.h"

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace terrain::globe {

namespace {

// π/4: the angle between a cube face's centre and its edge, seen from the centre.
constexpr double kFaceHalfAngle = std::numbers::pi / 4.0;

}  // namespace

PatchSurfaceFrame makePatchSurfaceFrame(const GlobePatchId& id, double requestedU0,
                                        double requestedV0, const glm::dvec3& camera) {
    // The stage measures Δα from the float u0, so the reference geometry must be that of the
    // float u0: rounded first, then everything else in double from it.
    const double u0 = static_cast<float>(requestedU0);
    const double v0 = static_cast<float>(requestedV0);
    const FaceFrame& face = faceFrame(id.face);
    const FacePoint reference = patchPoint(id, u0, v0);
    const double alpha0 = kFaceHalfAngle * (2.0 * reference.s - 1.0);
    const double beta0 = kFaceHalfAngle * (2.0 * reference.t - 1.0);
    const double cubeS0 = cubeCoordinate(reference.s);
    const double cubeT0 = cubeCoordinate(reference.t);
    const glm::dvec3 q0 =
        glm::dvec3(face.normal) + cubeS0 * glm::dvec3(face.right) + cubeT0 * glm::dvec3(face.down);
    const double length0 = glm::length(q0);
    const glm::dvec3 direction0 = q0 / length0;
    const double g0 = 1.0 - Wgs84::kEccentricitySquared * direction0.z * direction0.z;

    PatchSurfaceFrame frame;
    frame.normal = glm::vec3(face.normal);
    frame.right = glm::vec3(face.right);
    frame.down = glm::vec3(face.down);
    frame.alphaPerU = static_cast<float>((std::numbers::pi / 2.0) /
                                         static_cast<double>(patchesPerFaceSide(id.level)));
    frame.u0 = static_cast<float>(u0);
    frame.v0 = static_cast<float>(v0);
    frame.alpha0 = static_cast<float>(alpha0);
    frame.beta0 = static_cast<float>(beta0);
    frame.cubeS0 = static_cast<float>(cubeS0);
    frame.cubeT0 = static_cast<float>(cubeT0);
    frame.inverseLength0 = static_cast<float>(1.0 / length0);
    frame.direction0 = glm::vec3(direction0);
    frame.sqrtG0 = static_cast<float>(std::sqrt(g0));
    frame.primeVertical0 = static_cast<float>(Wgs84::kEquatorialRadius / std::sqrt(g0));
    frame.originFromCamera = glm::vec3(Wgs84::pointAlongNormal(direction0, 0.0) - camera);
    return frame;
}

glm::dvec2 nearestPatchCoordinates(const GlobePatchId& id, const glm::dvec3& cameraUp) {
    const FaceFrame& face = faceFrame(id.face);
    const double n = static_cast<double>(patchesPerFaceSide(id.level));
    const double along = glm::dot(cameraUp, glm::dvec3(face.normal));
    if (along <= 0.0) return {0.5, 0.5};  // the camera is over the far side: any point will do
    const double s = faceCoordinate(glm::dot(cameraUp, glm::dvec3(face.right)) / along);
    const double t = faceCoordinate(glm::dot(cameraUp, glm::dvec3(face.down)) / along);
    return {std::clamp(s * n - static_cast<double>(id.x), 0.0, 1.0),
            std::clamp(t * n - static_cast<double>(id.y), 0.0, 1.0)};
}

glm::vec3 cameraRelativePosition(const PatchSurfaceFrame& frame, float u, float v, float height) {
    // Cube coordinates as reference + small difference.
    const float deltaAlpha = frame.alphaPerU * (u - frame.u0);
    const float deltaBeta = frame.alphaPerU * (v - frame.v0);
    const float alpha = frame.alpha0 + deltaAlpha;
    const float beta = frame.beta0 + deltaBeta;
    const float deltaS = std::sin(deltaAlpha) / (std::cos(alpha) * std::cos(frame.alpha0));
    const float deltaT = std::sin(deltaBeta) / (std::cos(beta) * std::cos(frame.beta0));
    const float cubeS = frame.cubeS0 + deltaS;
    const float cubeT = frame.cubeT0 + deltaT;

    // Direction d = q / |q| as d0 + Δd.
    const glm::vec3 deltaQ = deltaS * frame.right + deltaT * frame.down;
    const glm::vec3 q0 = frame.normal + frame.cubeS0 * frame.right + frame.cubeT0 * frame.down;
    const float inverseLength = 1.0f / std::sqrt(1.0f + cubeS * cubeS + cubeT * cubeT);
    const float deltaLengthSquared =
        deltaS * (cubeS + frame.cubeS0) + deltaT * (cubeT + frame.cubeT0);
    const float deltaInverseLength = -deltaLengthSquared * inverseLength * frame.inverseLength0 /
                                     (1.0f / inverseLength + 1.0f / frame.inverseLength0);
    const glm::vec3 deltaDirection = deltaQ * inverseLength + q0 * deltaInverseLength;

    return surfaceOffsetFromDirection(frame.originFromCamera, frame.direction0, frame.sqrtG0,
                                      deltaDirection, height);
}

glm::vec3 surfaceOffsetFromDirection(const glm::vec3& originFromCamera, const glm::vec3& direction0,
                                     float sqrtG0, const glm::vec3& deltaDirection, float height) {
    constexpr float kA = static_cast<float>(Wgs84::kEquatorialRadius);
    constexpr float kE2 = static_cast<float>(Wgs84::kEccentricitySquared);
    const glm::vec3 direction = direction0 + deltaDirection;
    // S(d) − S(d0) = N·M·Δd + (N − N0)·M·d0.
    const float deltaG = -kE2 * deltaDirection.z * (direction.z + direction0.z);
    const float sqrtG = std::sqrt(sqrtG0 * sqrtG0 + deltaG);
    const float primeVertical = kA / sqrtG;
    const float deltaPrimeVertical = -kA * deltaG / (sqrtG * sqrtG0 * (sqrtG + sqrtG0));
    const glm::vec3 m(1.0f, 1.0f, 1.0f - kE2);
    const glm::vec3 deltaSurface =
        primeVertical * (m * deltaDirection) + deltaPrimeVertical * (m * direction0);
    return originFromCamera + deltaSurface + height * direction;
}

}  // namespace terrain::globe
