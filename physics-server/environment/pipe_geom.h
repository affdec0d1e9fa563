// Analytic pipe colliders: an ODE geom class (dCreateGeomClass) whose geoms
// are one piece of a PipeLayout (pipe_path.h): the exact interior of a
// cylinder or of a torus section, open at its ends. Contacts are on the inner
// wall; in dCollide(body geom, pipe geom) their normal points inwards, towards
// the axis (into the body), as ODE's plane does for a body on it.
//
// Colliders (the other geom's deepest points against the bore):
//  * sphere: exact, one contact;
//  * capsule: straight piece: the two ends of its axis segment clipped to
//    the piece (exact: distance from a line is convex along a segment);
//    elbow: 9 samples along the segment, local maxima refined by golden-
//    section search (the inner side of a bend touches a chord mid-way);
//  * cylinder: its two rim circles, 12 samples each, local maxima refined
//    (exact up to the refinement for straight pieces: the farthest point of
//    a convex body from a line is on its rims), plus the side line facing
//    outwards where a piece's end cuts it; elbow: also the side line facing
//    the bend's centre, sampled. Approximation: other side points of a
//    cylinder are not tested against the inner side of a bend;
//  * box: its 8 corners (exact for straight pieces) and where a piece's end
//    cuts its edges; elbow: its 12 edges, sampled. Approximation: face
//    interiors are not tested against the inner side of a bend.
// Open ends have no lip: a sample point past a piece's end plane does not
// touch that piece (a sphere rolling out of the exit drops once its centre is
// past the end; a capsule, cylinder or box is held up to the end plane).
// Tees and splits: a wall point inside the other piece's bore is an
// opening; near the edge of an opening contacts come from the sample points
// only (a body can catch on the edge slightly later or earlier than on a
// mesh). Against a piece with openings a cylinder's end faces are sampled
// too (13 points each): an opening's edge, the ridge and wedge between a
// split's outlets, can reach a face's interior. Box faces are not: a box
// meeting the wedge face first can sink onto it (not seen in the shipped
// scenes).
// Other geom classes (planes, meshes, rays) do not collide with a pipe.
// The deepest contacts are kept, at most the count dCollide asks for. No
// allocation.
#pragma once

#include <ode/ode.h>

#include "environment/pipe_path.h"

namespace chainsim {

// creates a geom for piece `piece` of layout in space; layout must outlive it
dGeomID pipe_geom_create(dSpaceID space, const PipeLayout* layout, int piece);

// the ODE class number of pipe geoms (registered on first use)
int pipe_geom_class();

}  // namespace chainsim
