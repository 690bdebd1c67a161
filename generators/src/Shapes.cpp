#include "Shapes.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace wirenet {

Eigen::Vector3d TriMesh::normal(size_t f) const {
    const auto& t = faces[f];
    return (vertices[t[1]] - vertices[t[0]]).cross(vertices[t[2]] - vertices[t[0]]).normalized();
}

void TriMesh::orientOutward(const Eigen::Vector3d& inside) {
    for (size_t f = 0; f < faces.size(); ++f) {
        const auto& t = faces[f];
        const Eigen::Vector3d c = (vertices[t[0]] + vertices[t[1]] + vertices[t[2]]) / 3.0;
        if (normal(f).dot(c - inside) < 0) std::swap(faces[f][1], faces[f][2]);
    }
}

MassProperties massProperties(const TriMesh& mesh, double mass) {
    // Sum over the signed tetrahedra (origin, face): volume, first and second moments.
    double vol = 0;
    Eigen::Vector3d first = Eigen::Vector3d::Zero();
    Eigen::Matrix3d second = Eigen::Matrix3d::Zero();  // integral of x x^T dV
    const Eigen::Matrix3d canonical = (Eigen::Matrix3d::Identity() + Eigen::Matrix3d::Ones()) / 120.0;
    for (const auto& t : mesh.faces) {
        Eigen::Matrix3d A;
        A << mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]];
        const double det = A.determinant();
        vol += det / 6.0;
        first += det / 24.0 * (A.col(0) + A.col(1) + A.col(2));
        second += det * A * canonical * A.transpose();
    }
    MassProperties p;
    p.volume = vol;
    p.centroid = first / vol;
    if (mass > 0) {
        const double rho = mass / vol;
        const Eigen::Matrix3d S = rho * (second - vol * p.centroid * p.centroid.transpose());
        p.inertia = S.trace() * Eigen::Matrix3d::Identity() - S;
    }
    return p;
}

namespace {

// Ring of n vertices of radius r at height z; returns the index of the first one.
// The vertices sit half a segment off the x axis, so that for n divisible by 4 no facet edge of an
// apex fan lies in the planes x = 0, y = 0 (or the diagonals for n divisible by 8): net nodes stay
// exactly in those planes by symmetry, and LIGGGHTS drops the contact of a sphere whose centre
// projects exactly onto an edge between two nearly coplanar facets (the edge is inactive for
// both, and neither face claims the point) until the overlap is large.
int addRing(TriMesh& m, double r, double z, int n) {
    const int first = int(m.vertices.size());
    for (int i = 0; i < n; ++i) {
        const double phi = 2 * M_PI * (i + 0.5) / n;
        m.vertices.emplace_back(r * std::cos(phi), r * std::sin(phi), z);
    }
    return first;
}

void fan(TriMesh& m, int centre, int ring, int n) {
    for (int i = 0; i < n; ++i) m.faces.push_back({centre, ring + i, ring + (i + 1) % n});
}

// A flat polygon (ring of n vertices) without a centre vertex: one central triangle of three
// vertices about 120 degrees apart, each remaining cap fanned from its first vertex. The centre,
// where the net's centre node rests on a flat platter tip, then lies inside a facet, about half a
// radius from its edges, never on an edge or vertex (see addRing).
void coveredDisc(TriMesh& m, int ring, int n) {
    const int k[3] = {0, n / 3, 2 * n / 3};
    m.faces.push_back({ring + k[0], ring + k[1], ring + k[2]});
    for (int c = 0; c < 3; ++c) {
        const int from = k[c], to = c < 2 ? k[c + 1] : n;
        for (int j = from + 1; j < to; ++j) m.faces.push_back({ring + from, ring + j, ring + (j + 1) % n});
    }
}

// Band between two rings of different vertex counts (both from addRing): walk both in angle
// order, each triangle advancing the ring whose next vertex comes first.
void zipBand(TriMesh& m, int ringA, int na, int ringB, int nb) {
    auto angle = [](int k, int n) { return 2 * M_PI * (k + 0.5) / n; };
    int i = 0, j = 0;
    while (i < na || j < nb) {
        const bool advanceA = j == nb || (i < na && angle(i + 1, na) < angle(j + 1, nb));
        if (advanceA) {
            m.faces.push_back({ringA + i, ringB + j % nb, ringA + (i + 1) % na});
            ++i;
        } else {
            m.faces.push_back({ringA + i % na, ringB + j, ringB + (j + 1) % nb});
            ++j;
        }
    }
}

void band(TriMesh& m, int ringA, int ringB, int n) {
    for (int i = 0; i < n; ++i) {
        const int j = (i + 1) % n;
        m.faces.push_back({ringA + i, ringB + i, ringB + j});
        m.faces.push_back({ringA + i, ringB + j, ringA + j});
    }
}

}  // namespace

TriMesh ShapeBuilder::semiSpheroid(double radius, double height, int segments) {
    // Rings at equal steps of the polar angle from the apex (0, 0, -h) to the rim.
    TriMesh m;
    const int rings = std::max(4, segments / 4);
    m.vertices.emplace_back(0, 0, -height);
    int prev = -1;
    for (int j = 1; j <= rings; ++j) {
        const double th = 0.5 * M_PI * j / rings;
        const double z = j == rings ? 0.0 : -height * std::cos(th);
        const int ring = addRing(m, radius * std::sin(th), z, segments);
        if (j == 1) fan(m, 0, ring, segments);
        else band(m, prev, ring, segments);
        prev = ring;
    }
    m.vertices.emplace_back(0, 0, 0);
    fan(m, int(m.vertices.size()) - 1, prev, segments);
    m.orientOutward({0, 0, -0.5 * height});
    return m;
}

TriMesh ShapeBuilder::cone(double radius, double height, int segments, double tipRadius) {
    TriMesh m;
    if (tipRadius > 0) {
        // Tip disc: an octagon of half the tip radius covered without a centre vertex, and a
        // flat annulus out to the tip ring. Covering the whole ring without a centre vertex
        // would need slivers that LIGGGHTS rejects as a bad mesh (angles near 180 deg).
        const int inner = addRing(m, 0.5 * tipRadius, -height, 8);
        coveredDisc(m, inner, 8);
        const int tip = addRing(m, tipRadius, -height, segments);
        zipBand(m, inner, 8, tip, segments);
        // Lateral surface: rings doubling in radius, so no facet is a sliver (LIGGGHTS rejects
        // angles below about 0.26 deg; one band from a 2 cm tip ring would make 0.2 deg). The
        // quads stay planar: their vertices share azimuths on the exact cone.
        int prev = tip;
        for (double r = 2 * tipRadius; r < 0.75 * radius; r *= 2) {
            const int ring = addRing(m, r, -height * (radius - r) / (radius - tipRadius), segments);
            band(m, prev, ring, segments);
            prev = ring;
        }
        const int base = addRing(m, radius, 0.0, segments);
        band(m, prev, base, segments);
        m.vertices.emplace_back(0, 0, 0);
        fan(m, int(m.vertices.size()) - 1, base, segments);
    } else {
        m.vertices.emplace_back(0, 0, -height);
        const int ring = addRing(m, radius, 0.0, segments);
        fan(m, 0, ring, segments);
        m.vertices.emplace_back(0, 0, 0);
        fan(m, int(m.vertices.size()) - 1, ring, segments);
    }
    m.orientOutward({0, 0, -0.25 * height});
    return m;
}

TriMesh ShapeBuilder::truncatedCube(double side, double cut) {
    TriMesh m;
    const double h = 0.5 * side, k = h - cut;
    // Each cube corner becomes three vertices, one on each of its edges.
    for (int sx : {-1, 1})
        for (int sy : {-1, 1})
            for (int sz : {-1, 1}) {
                const int a = int(m.vertices.size());
                m.vertices.emplace_back(sx * k, sy * h, sz * h);
                m.vertices.emplace_back(sx * h, sy * k, sz * h);
                m.vertices.emplace_back(sx * h, sy * h, sz * k);
                m.faces.push_back({a, a + 1, a + 2});  // corner triangle
            }
    // Each cube face: the octagon of the vertices in its plane, sorted by angle, cut into six
    // triangles by diagonals that avoid the face centre (no diagonal joins opposite vertices
    // i, i+4). A plain fan would put the diagonal 0-4 through the centre, where the panel's
    // centre node hits the face exactly on an edge between coplanar facets: LIGGGHTS drops
    // such a contact (see addRing).
    static const int kOctagon[6][3] = {{0, 1, 2}, {0, 2, 3}, {3, 4, 5}, {0, 3, 5}, {5, 6, 7}, {0, 5, 7}};
    for (int axis = 0; axis < 3; ++axis)
        for (int s : {-1, 1}) {
            std::vector<int> poly;
            for (int v = 0; v < int(m.vertices.size()); ++v)
                if (m.vertices[v][axis] == s * h) poly.push_back(v);
            const int u = (axis + 1) % 3, w = (axis + 2) % 3;
            std::sort(poly.begin(), poly.end(), [&](int a, int b) {
                return std::atan2(m.vertices[a][w], m.vertices[a][u]) <
                       std::atan2(m.vertices[b][w], m.vertices[b][u]);
            });
            for (const auto& t : kOctagon) m.faces.push_back({poly[t[0]], poly[t[1]], poly[t[2]]});
        }
    m.orientOutward(Eigen::Vector3d::Zero());
    return m;
}

double ShapeBuilder::semiSpheroidVolume(double r, double h) { return 2.0 / 3.0 * M_PI * r * r * h; }

double ShapeBuilder::coneVolume(double r, double h, double a) { return M_PI * h * (r * r + r * a + a * a) / 3.0; }

double ShapeBuilder::truncatedCubeVolume(double s, double c) { return s * s * s - 4.0 / 3.0 * c * c * c; }

double ShapeBuilder::truncatedCubeInertia(double s, double c, double mass) {
    // Cube minus 8 corner tetrahedra (legs c at distance h = s/2 from the centre per axis):
    // per tetrahedron, integral of (y^2 + z^2) = 2 (h^2 c^3/6 - 2 h c^4/24 + c^5/60).
    const double h = 0.5 * s;
    const double rho = mass / truncatedCubeVolume(s, c);
    const double corner = 2 * (h * h * c * c * c / 6 - h * std::pow(c, 4) / 12 + std::pow(c, 5) / 60);
    return rho * (std::pow(s, 5) / 6 - 8 * corner);
}

const char* shapeKindName(ShapeKind k) {
    switch (k) {
        case ShapeKind::Spheroid: return "spheroid";
        case ShapeKind::Cone: return "cone";
        case ShapeKind::TruncatedCube: return "truncated-cube";
    }
    return "spheroid";
}

bool parseShapeKind(const std::string& text, ShapeKind& k) {
    static const ShapeKind all[] = {ShapeKind::Spheroid, ShapeKind::Cone, ShapeKind::TruncatedCube};
    return parseByName(text, all, shapeKindName, k);
}

void ShapeParams::validate() const {
    if (kind == ShapeKind::TruncatedCube && !(cornerCut < 0.5 * side))
        throw UsageError("--corner-cut must be < --side/2 (got " + fmt(cornerCut) + " >= " + fmt(0.5 * side) + ")");
    if (kind == ShapeKind::Cone && !(tipRadius < radius))
        throw UsageError("--tip-radius must be < --radius (got " + fmt(tipRadius) + " >= " + fmt(radius) + ")");
}

TriMesh ShapeParams::mesh() const {
    switch (kind) {
        case ShapeKind::Spheroid: return ShapeBuilder::semiSpheroid(radius, height, resolution);
        case ShapeKind::Cone: return ShapeBuilder::cone(radius, height, resolution, tipRadius);
        case ShapeKind::TruncatedCube: return ShapeBuilder::truncatedCube(side, cornerCut);
    }
    return TriMesh();
}

double ShapeParams::volume() const {
    switch (kind) {
        case ShapeKind::Spheroid: return ShapeBuilder::semiSpheroidVolume(radius, height);
        case ShapeKind::Cone: return ShapeBuilder::coneVolume(radius, height, tipRadius);
        case ShapeKind::TruncatedCube: return ShapeBuilder::truncatedCubeVolume(side, cornerCut);
    }
    return 0;
}

}  // namespace wirenet
