#pragma once
// Closed, outward-oriented solids built procedurally: the shapes data_synthetic/ writes as object
// files (barge, small boat, buoy, pier with pilings, step target) and the tests use as exact
// references (a box has volume lx * ly * lz to rounding).
//
// Object frame: x = starboard (beam), y = forward (bow), z = up, metres. Floating shapes have their
// keel at z = 0; `draft` placement then lowers them.
#include <string>
#include <vector>

#include "core/mesh.h"

namespace littoral::scenegen {

// Axis-aligned box [-lx/2, lx/2] x [-ly/2, ly/2] x [z0, z0 + lz]; top face slot `topSlot`, others
// slot `sideSlot`. 8 vertices, 12 triangles.
TriMesh makeBox(double lx, double ly, double lz, double z0 = 0.0, uint16_t sideSlot = 0, uint16_t topSlot = 0);

// Barge: a box hull (slot 0) with its deck (slot 1): beam x length x depth.
TriMesh makeBarge(double beam, double length, double depth);

// Small boat: a lofted V-bottom hull (slot 0: hull) with a flat deck (slot 1: deck), transom at
// the stern and a narrow stem at the bow. `stations` cross-sections along the length.
TriMesh makeBoat(double length, double beam, double depth, int stations = 16);

// Vertical cylinder of radius r from z0 to z1 with `segments` sides (slot `slot`); the caps are
// fanned from their centres.
TriMesh makeCylinder(double r, double z0, double z1, int segments = 16, uint16_t slot = 0);

// Spar buoy: a cylinder of radius r and height h with a conical top of height 0.5 r (slot 0).
TriMesh makeBuoy(double radius, double height, int segments = 24);

struct PierParams {
    double length = 20;          // m along y (out from the shore)
    double width = 3;            // m along x
    double deckThickness = 0.4;  // m
    double deckBottom = 1.2;     // m above the still-water level (z of the deck's underside)
    double pilingRadius = 0.2;   // m
    double pilingSpacing = 5;    // m between piling pairs along the pier
    double pilingBottom = -6;    // m, z where the pilings end (below the seabed)
    int segments = 12;
};
// Pier: a deck box (slot 0) fused with pairs of cylindrical pilings (slot 1) by a CGAL union, so
// the result is one closed manifold solid.
TriMesh makePier(const PierParams& p);

// Step target: a square pedestal of side `size` and height `height` with its top at z = 0, the
// top split into a bright half (x < 0, slot 0) and a dark half (x > 0, slot 1); sides and bottom
// slot 1.
TriMesh makeStepTarget(double size, double height);

}  // namespace littoral::scenegen
