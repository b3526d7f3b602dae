/* caustic.h - the light a glass sphere focuses onto a diffuse vertex,
 * estimated through the sphere: manifold next-event estimation for a chain
 * of two refractions, solved exactly in its plane.
 *
 * From a diffuse point x, a light point y and a glass sphere (centre c),
 * a path x -> p1 (into the sphere) -> p2 (out of it) -> y refracts in the
 * plane of x, c and y, so the chain is a root of a function g of one
 * number: the offset b of the ray from x from the line x-c (g: how far y
 * lies from the chain's exit ray). Every root is found: a scan of the
 * offsets (denser toward grazing), the Illinois method on each sign
 * change, and a golden-section search of g's extremum wherever three
 * samples turn toward zero (the two roots about a fold of the chains, at
 * the caustic's bright core). Each chain is weighed by its Fresnel
 * transmission and by the solid angle at x per unit of the light's area
 * (its motion with b by central differences, with the turn about the
 * axis x-c exactly). Only +, -, *, / and sqrt: the same bits on every
 * machine.
 *
 * The scattered path from such a vertex that refracts into and out of the
 * sphere and meets an emitter finds the same chains: the two estimates
 * are combined by multiple importance sampling (power heuristic; the
 * estimate's density is the light point's over the solid angle per area,
 * the path's the scattering's times the two refractions' chances), so
 * each strategy keeps the chains it finds best (the scattered path those
 * near a fold, where the solid angle per area vanishes). Whether a vertex
 * estimates (rt_caustic_gate) is a rule of its position alone, so either
 * way the sum is unbiased. Core-internal. */
#ifndef RT_CAUSTIC_H
#define RT_CAUSTIC_H

#include <stdint.h>

#include "render.h"
#include "vec.h"
#include "world.h"

/* Whether the diffuse vertex at x estimates a glass sphere's caustic here:
 * 1, with *target (lights.h's target index), in the sphere's shadow
 * (rt_lights_target_between), where the light it focuses falls; else 0. */
int rt_caustic_gate(const rt_renderer *r, rt_vec3 x, uint32_t *target);

/* The light reaching the pixel from x (normal n) through target sphere
 * `target`, for the light point drawn by u and u2 (as rt_lights_point):
 * weight (the path's throughput times the albedo) times cos / pi, times
 * each chain's emission, transmission and solid angle per area, over the
 * point's density, weighted (above). Adds its shadow rays to *segments. */
rt_vec3 rt_caustic_direct(const rt_renderer *r, rt_vec3 x, rt_vec3 n,
                          rt_vec3 weight, double time, uint32_t target,
                          double u, uint64_t u2, uint64_t *segments);

/* The weight of the light a scattered path from x (normal n, direction w)
 * finds at hit h of an emitter, point y (normal nl), after refracting into
 * and out of target sphere `target` at a vertex that estimated the light
 * through it (rt_caustic_direct): multiple importance sampling against
 * that estimate, which weighs the same chain by the complement. */
double rt_caustic_weight(const rt_renderer *r, rt_vec3 x, rt_vec3 n, rt_vec3 w,
                         uint32_t target, const rt_whit *h, rt_vec3 y,
                         rt_vec3 nl, double time);

#endif
