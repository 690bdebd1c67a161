#include "FenceOutput.h"

#include <cmath>
#include <map>

namespace wirenet {
namespace {

Json idArray(const std::vector<int>& nodes) {
    Json a = Json::array();
    for (int n : nodes) a.push(n + 1);
    return a;
}

// The types a fence adds to the panels' 1-8 atom and 1-4 bond types.
void nameFenceTypes(NetDescription& d) {
    d.atomTypes = ftype::Count;
    d.bondTypes = fbond::Count;
    d.atomTypeNames.insert({{ftype::SupportRope, "support_rope"}, {ftype::UpslopeRope, "upslope_rope"},
                            {ftype::Post, "post"}, {ftype::PostBase, "post_base"}, {ftype::PostHead, "post_head"},
                            {ftype::Anchor, "anchor"}});
    d.bondTypeNames.insert({{fbond::SupportRope, "support_rope"}, {fbond::Brake, "brake"}, {fbond::Upslope, "upslope"},
                            {fbond::UpslopeBrake, "upslope_brake"}, {fbond::Post, "post"}});
}

// The "fence" object: the layout as built.
Json layoutJson(const FenceParams& p, const FenceModel& f) {
    Json j = Json::object();
    if (p.net == NetKind::Compound)
        j.set("hex_y", 0.5 * (p.panel.hex.nodeDiameter + p.panel.square.nodeDiameter)).set("square_y", 0.0)
            .set("tie_every", p.panel.tieEvery).set("tie_bond_type", p.panel.tieType);
    j.set("net", netKindName(p.net)).set("modules", p.modules).set("spacing", p.spacing).set("height", p.height);
    Json postX = Json::array();
    for (int i = 0; i <= p.modules; ++i) postX.push(p.postX(i));
    j.set("post_x", postX);
    j.set("shackle_gap", p.shackleGap).set("post_gap", p.sideGap()).set("panel_nodes", f.panelNodes)
        .set("panel_bonds", f.panelBonds);
    j.set("anchor_distance", p.anchorDistance).set("bottom_anchor_distance", p.bottomAnchorDistance);
    j.set("upslope_distance", p.upslopeDistance).set("upslope_height", p.upslopeHeight).set("upslope_sag", p.upslopeSag).set("post_tilt_deg", p.postTilt);
    j.set("coordinates", "x along the fence (centred on the fence), y upslope: the block comes from +y and "
          "travels towards -y, z up; post bases at z = 0, heads at z = height; the net in the plane y = 0; "
          "a panel's (x, y, z) is (x_c + x, z, height/2 + y) here; with post_tilt_deg > 0 all of it but the upslope ropes "
          "is then turned about the x axis at the ground, the heads towards -y");
    return j;
}

Json bondFamilies() {
    Json j = Json::object();
    for (const auto& kv : std::map<int, std::string>{{1, "DT"}, {2, "SW"}, {3, "selvedge"}, {4, "rope"},
                                                      {5, "rope"}, {6, "brake"}, {7, "upslope"}, {8, "brake"}, {9, "post"}})
        j.set(std::to_string(kv.first), kv.second);
    return j;
}

Json molecules() {
    Json j = Json::object();
    j.set("1", "hexagonal layer").set("2", "square layer").set("3", "top support rope")
        .set("4", "bottom support rope").set("5", "upslope ropes").set("6", "posts").set("7", "anchors");
    return j;
}

Json anchorsJson(const FenceModel& f) {
    Json a = Json::array();
    for (const auto& an : f.anchors) {
        Json j = Json::object();
        j.set("id", an.atom + 1).set("name", an.name).set("rope", an.rope).set("position", Json::vec3(f.model.nodes[an.atom].x));
        a.push(j);
    }
    return a;
}

Json shacklesJson(const FenceParams& p, const FenceModel& f, const std::string& file) {
    Json ropes = Json::array();
    std::map<int, long> perRope;
    for (const auto& s : f.shackles) ++perRope[s.rope];
    for (const auto& r : f.ropes) {
        Json j = Json::object();
        j.set("id", r.id).set("name", r.name).set("kind", r.kind).set("atoms", long(r.atoms.size()))
            .set("shackles", perRope[r.id]);
        ropes.push(j);
    }
    Json j = Json::object();
    j.set("file", file).set("count", long(f.shackles.size())).set("ropes", ropes);
    j.set("max_distance", f.shackleMaxDistance).set("gap", p.shackleGap).set("post_gap", p.sideGap())
        .set("side", p.sideShackles ? "post" : "none");
    j.set("note", "net edge nodes on the top and bottom edge (corners included) hang on the top and "
          "bottom support rope, gap from it, the module sides on the neighbouring post (side post), "
          "post_gap from its axis, the post heads on the top rope (sliding guide) and the post bases "
          "on the bottom rope; a shackle is never an atom of its own rope");
    return j;
}

// The support and upslope ropes: sections, masses, bond types and counts.
Json ropesJson(const FenceParams& p, const FenceModel& f) {
    Json support = Json::object();
    support.set("diameter", p.supportDiameter).set("fill", p.fill).set("mass_per_metre", p.ropeMass(p.supportDiameter))
        .set("bond_type", fbond::SupportRope).set("family", "rope").set("brake_bond_type", fbond::Brake)
        .set("brakes_per_end", p.brakes).set("segment_target", p.ropeSegment).set("span_bond", p.spanBond())
        .set("span_bonds", p.spanBonds()).set("top_leg_bonds", p.topLegBonds()).set("bottom_leg_bonds", p.bottomLegBonds())
        .set("node_type", ftype::SupportRope).set("node_diameter", p.supportDiameter);
    Json upslopeIds = Json::array();
    for (const auto& r : f.upslopeRopes) upslopeIds.push(idArray(r));
    // from the leaned head down to the anchor
    const Eigen::Vector3d head = p.lean({0.0, 0.0, p.height});
    Json upslope = Json::object();
    upslope.set("diameter", p.upslopeDiameter).set("fill", p.fill).set("mass_per_metre", p.ropeMass(p.upslopeDiameter))
        .set("bond_type", fbond::Upslope).set("family", "upslope").set("brake_bond_type", fbond::UpslopeBrake)
        .set("brakes", p.upslopeBrakes).set("bonds", p.upslopeBonds()).set("length", p.upslopeLength())
        .set("angle_deg", std::atan2(head.z() - p.upslopeHeight, p.upslopeDistance - head.y()) * 180.0 / M_PI)
        .set("node_type", ftype::UpslopeRope).set("node_diameter", p.upslopeDiameter).set("atoms", upslopeIds);
    Json j = Json::object();
    j.set("support", support).set("upslope", upslope);
    j.set("mass_rule", "fill x density x pi d^2/4 per metre, half of each bond to each of its nodes");
    return j;
}

// The posts: the beam section (HEA 200 unless --post-area/-iy/-iz/-j say otherwise) and its steel.
Json postsJson(const FenceParams& p) {
    const bool hea = p.postArea == kHeaArea && p.postIy == kHeaIy && p.postIz == kHeaIz && p.postJ == kHeaJ;
    Json section = Json::object();
    section.set("profile", hea ? "HEA 200" : "user").set("A", p.postArea).set("Iy", p.postIy).set("Iz", p.postIz)
        .set("J", p.postJ);
    if (hea) section.set("source", "EN 10365:2017 HEA 200 (ArcelorMittal sales programme tables): A 53.83 cm2, "
                         "Iy 3692 cm4, Iz 1336 cm4, It 20.98 cm4, 42.3 kg/m");
    Json j = Json::object();
    j.set("count", p.modules + 1).set("elements", p.postElements).set("height", p.height)
        .set("bond_type", fbond::Post).set("family", "post").set("section", section)
        .set("orient", Json::vec3(Eigen::Vector3d::UnitX()))
        .set("orient_note", "the section's y axis (strong axis, Iy, flanges parallel to the fence) along the fence, x: "
             "bending under a load along y is resisted by E Iy; deck: bond_coeff T beam section A Iy Iz J orient 1 0 0 E .. nu ..")
        .set("E", kSteelE).set("nu", kSteelNu).set("density", p.density).set("mass_per_metre", p.density * p.postArea)
        .set("node_diameter", p.postNodeDiameter).set("base", "hinged: hold the translation of post_bases only");
    if (p.postNodeDiameter == kHeaWidth)
        j.set("node_diameter_note", "the HEA 200's width, its flange width b = 200 mm (EN 10365:2017): the net "
              "touches the post at its flange, b/2 from the axis, and the sphere's rotary inertia 0.4 m r^2 is "
              "within a factor of two of the section's (Iy/A) m");
    return j;
}

Json massJson(const FenceModel& f) {
    Json j = Json::object();
    j.set("net", f.netMass).set("support_ropes", f.supportMass).set("upslope_ropes", f.upslopeMass)
        .set("posts", f.postMass).set("total", f.model.totalMass());
    return j;
}

}  // namespace

NetDescription fenceDescription(const FenceParams& p, const FenceModel& f, const std::string& command,
                                const std::string& shacklesFile) {
    NetDescription d = panelDescription("fence");
    d.command = command;
    nameFenceTypes(d);
    d.centre = f.moduleCentres[p.modules / 2];  // the middle module, the impacted one
    d.normal = p.lean(Eigen::Vector3d::UnitY());
    d.width = p.panelWidth();
    d.height = p.panelHeight();
    const CompoundParams module = p.module();
    if (p.net != NetKind::Square) HexPanel(module.hex).describe(d, f.panel);
    if (p.net != NetKind::Hex) SquarePanel(module.square).describe(d, f.panel);
    d.extra = layoutJson(p, f);

    Json centres = Json::array();
    for (const auto& c : f.moduleCentres) centres.push(Json::vec3(c));
    d.top.set("impact_target", Json::vec3(d.centre));
    d.top.set("module_centres", centres).set("post_bases", idArray(f.postBases)).set("post_heads", idArray(f.postHeads));
    d.top.set("anchors", anchorsJson(f)).set("shackles", shacklesJson(p, f, shacklesFile));
    d.top.set("bond_families", bondFamilies()).set("molecules", molecules());
    d.top.set("ropes", ropesJson(p, f)).set("posts", postsJson(p)).set("mass", massJson(f));
    return d;
}

void writeShackles(std::ostream& os, const FenceModel& f, const std::string& command) {
    os << "# wirenet-gen " << command << "\n";
    os << "# ropes: ROPE_ID N ID_1 .. ID_N (atom IDs in order along the rope, anchors at the ends)\n";
    os << "# shackles: ATOM_ID ROPE_ID (the atom slides along the rope; it is not one of its atoms)\n";
    for (const auto& r : f.ropes) os << "# rope " << r.id << ": " << r.name << " (" << r.kind << ")\n";
    os << "ropes " << f.ropes.size() << "\n";
    for (const auto& r : f.ropes) {
        os << r.id << " " << r.atoms.size();
        for (int a : r.atoms) os << " " << a + 1;
        os << "\n";
    }
    os << "shackles " << f.shackles.size() << "\n";
    for (const auto& s : f.shackles) os << s.atom + 1 << " " << s.rope << "\n";
}

}  // namespace wirenet
