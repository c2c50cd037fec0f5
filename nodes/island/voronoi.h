#pragma once
// Voronoi diagrams clipped to a rectangle, and Lloyd relaxation, for the island family. The plain interface
// of the CGAL core (voronoi_cgal.cpp is the only file that includes CGAL headers).
//
// The diagram is the dual of CGAL's Delaunay triangulation (exact predicates, inexact constructions) of the
// sites (inserted along a Hilbert curve) plus their mirror images across the rectangle's sides near the
// border: the bisector of a site and its mirror is the side itself, so the cells of the sites are exactly
// their Voronoi cells clipped to the rectangle. Sites are snapped to a lattice of 2^-30 of the rectangle's longer side
// so the mirrors are exact and the four-point circles they form are recognised by the exact in-circle predicate; faces
// sharing a circumcircle become one corner (no zero-length edges).
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec2.hpp>

#include "graph/polygon_map.h"

namespace orogen {
class ExecContext;
}

namespace orogen::island {

// The polygon map of `sites` clipped to [lo, hi]: cells (centre = the snapped site, corners counter-
// clockwise), corners (Voronoi vertices; those on the rectangle's sides flagged `border` and placed exactly
// on them), edges (Voronoi edges; cells[1] = -1 along the rectangle), neighbours. No attributes.
// Throws std::runtime_error if two sites coincide after snapping or a site lies outside the rectangle.
PolygonMap voronoi_diagram(std::span<const glm::dvec2> sites, glm::dvec2 lo, glm::dvec2 hi,
                           const ExecContext* ctx = nullptr);

// Reorders points along a Hilbert curve (deterministic), so that points near in the list are near in the
// plane: cells numbered in this order make the polygon map's loops cache friendly.
void hilbert_sort(std::vector<glm::dvec2>& points);

// Area and area centroid of a simple polygon (shoelace formula; counter-clockwise gives a positive area).
double polygon_area(std::span<const glm::dvec2> polygon);
glm::dvec2 polygon_centroid(std::span<const glm::dvec2> polygon);

// The corners of cell `c` as positions.
std::vector<glm::dvec2> cell_polygon(const PolygonMap& map, int c);

// Centroidal Voronoi energy: sum over cells of the integral of |x - site|^2 over the cell (m^4). Lloyd's
// algorithm never increases it.
double centroidal_energy(const PolygonMap& map);

// `passes` iterations of Lloyd's algorithm (Lloyd 1982): each site moves to the area centroid of its
// clipped Voronoi cell. Returns the relaxed sites; `energy`, if given, receives the centroidal energy of the
// diagram before each pass and after the last (passes + 1 values).
std::vector<glm::dvec2> lloyd_relax(std::vector<glm::dvec2> sites, glm::dvec2 lo, glm::dvec2 hi, int passes,
                                    std::vector<double>* energy = nullptr, const ExecContext* ctx = nullptr);

// voronoi_diagram(lloyd_relax(sites, ...)) in one go: every diagram inserts the sites in the Hilbert order of
// the first one (the sites move by less than a cell per pass), so the order is computed once.
PolygonMap relaxed_voronoi_diagram(std::vector<glm::dvec2> sites, glm::dvec2 lo, glm::dvec2 hi, int passes,
                                   std::vector<double>* energy = nullptr, const ExecContext* ctx = nullptr);

}  // namespace orogen::island
