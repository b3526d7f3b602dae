/* bvh_node.h - the BVH's memory layout, shared by its build (bvh_build.c)
 * and its traversals (bvh.c); nothing outside the BVH includes it. */
#ifndef RT_BVH_NODE_H
#define RT_BVH_NODE_H

#include <stdint.h>

#include "bvh.h"
#include "fbox.h"

#define WIDTH FBOX_WIDTH /* children per node: one AVX register, two SSE2 ones */

/* Spheres per leaf, at most. One: in an 8-wide tree a leaf takes a child
 * slot, not a node of its own, and one sphere's box is the tightest cull
 * the box test can make. Rays of the final scene tested 2.00 spheres each
 * (the ground included) against 3.04 with leaves of up to two, the earlier
 * rule; whole renders ran 2.4 % faster (scripts/ab_render.sh, paired
 * rounds). A larger value lets the SAH make leaves of up to that many
 * spheres, for experiments. */
#ifndef LEAF_MAX
#define LEAF_MAX 1
#endif
/* A leaf's child code keeps count - 1 in 4 bits (emit_leaf). */
_Static_assert(LEAF_MAX >= 1 && LEAF_MAX <= 16, "LEAF_MAX must be 1 to 16");
#ifndef TRAV_COST
#define TRAV_COST 1.0
#endif
#ifndef BINS
#define BINS 16
#endif
#define OUTSIDE_MAX 4 /* spheres tested before the traversal, at most */

/* Entries the traversal stack can need: each node pushes WIDTH - 1 at most,
 * once per level, and the build keeps the tree shallower than this (splits
 * go to the median past depth 48, so 48 + 32 levels for 2^32 spheres). */
#define STACK_MAX ((WIDTH - 1) * 80)

typedef struct node {
    _Alignas(64) float bmin[3][WIDTH]; /* rows x, y, z of the children's boxes */
    float bmax[3][WIDTH];
    int32_t child[WIDTH]; /* >= 0: node index; < 0: ~(start << 4 | (count - 1)) */
    int32_t nchild;       /* bit mask of the child slots in use */
} node;

typedef struct prim {
    double c[3];
    double r2;
    uint32_t index;
    uint32_t pad;
} prim;

struct rt_bvh {
    node *nodes;
    int n_nodes, cap_nodes;
    prim *prims; /* the tree's spheres, in leaf order */
    uint32_t n_prims;
    int depth, leaves;
    prim outside[OUTSIDE_MAX]; /* spheres left out of the tree */
    int n_outside;
    int avx; /* rt_bvh_closest runs the AVX box test */
};

#endif
