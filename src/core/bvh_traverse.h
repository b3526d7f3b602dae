/* bvh_traverse.h - the closest-hit traversal of bvh.c, which includes it
 * once per instruction set: it defines TRAVERSE (the function's name), with
 * the AVX box test when TRAV_AVX is 1, else the SSE2 one (when the build has
 * SSE2) or the portable one, as the argument `simd` says. Not a header to include anywhere else.
 *
 * Ordered depth-first traversal: the nearest hit child is visited next
 * without touching the stack, the others are pushed far to near with their
 * entry distance, and popped entries beyond the current closest hit are
 * dropped. Boxes are tested against the planes a ray meets first and last
 * (chosen once per ray by the direction's signs), so no min/max swap is
 * needed per box. */

static inline __attribute__((always_inline)) int TRAVERSE(const rt_bvh *b, const rt_ray *ray, double tmin,
                                                           double tmax, rt_hit *hit, const int simd,
                                                           rt_bvh_counts *counts)
{
    if (!b->n_nodes) /* an empty scene: the tree keeps one sphere at least */
        return 0;
    const double a = rt_v3_len2(ray->dir);
    double closest = tmax;
    uint32_t best = UINT32_MAX;
    const float fo[3] = {(float)ray->orig.x, (float)ray->orig.y, (float)ray->orig.z};
    const float fi[3] = {safe_inv(ray->dir.x), safe_inv(ray->dir.y), safe_inv(ray->dir.z)};
    /* Row of the near plane per axis in node.bmin/bmax, seen as float[6][WIDTH]. */
    /* From the sign bits, without branches: the signs of secondary rays are
     * random, and a mispredicted branch costs more than the arithmetic. */
    const int sx = sign_bit(fi[0]), sy = sign_bit(fi[1]), sz = sign_bit(fi[2]);
    const int nx = 3 * sx, ny = 1 + 3 * sy, nz = 2 + 3 * sz;
    const int rws[6] = {nx, ny, nz, 3 - nx, 5 - ny, 7 - nz}; /* the near planes' rows, then the far ones' */
    const float tmin_f = near_bound(tmin);
#if TRAV_AVX
    (void)simd;
    const fbox_ray8 vr = {_mm256_set1_ps(fo[0]), _mm256_set1_ps(fo[1]), _mm256_set1_ps(fo[2]), _mm256_set1_ps(fi[0]),
                          _mm256_set1_ps(fi[1]), _mm256_set1_ps(fi[2]), _mm256_set1_ps(tmin_f)};
#elif RT_BVH_HAVE_SSE2
    const fbox_ray4 vr = {_mm_set1_ps(fo[0]), _mm_set1_ps(fo[1]), _mm_set1_ps(fo[2]), _mm_set1_ps(fi[0]),
                          _mm_set1_ps(fi[1]), _mm_set1_ps(fi[2]), _mm_set1_ps(tmin_f)};
#else
    (void)simd;
#endif
    /* The spheres outside the tree first: a hit on one bounds the traversal. */
    test_spheres(b->outside, (uint32_t)b->n_outside, ray, a, tmin, &closest, &best, counts);
    float tfar_f = far_bound(closest);
    int32_t stack_node[STACK_MAX];
    float stack_t[STACK_MAX];
    int sp = 0;
    int32_t code = 0;
    for (;;) {
        if (code < 0) {
            uint32_t count;
            const prim *p = leaf_prims(b, code, &count);
            if (test_spheres(p, count, ray, a, tmin, &closest, &best, counts))
                tfar_f = far_bound(closest);
        } else {
            const node *n = &b->nodes[code];
            if (counts)
                counts->nodes++;
            const float(*rows)[WIDTH] = (const float(*)[WIDTH])n->bmin; /* bmin then bmax: 6 rows */
            float tn[WIDTH];
            int mask;
#if TRAV_AVX
            mask = fbox_avx(rows, rws, &vr, tfar_f, tn);
#elif RT_BVH_HAVE_SSE2
            mask = simd ? fbox_sse(rows, rws, &vr, tfar_f, tn) : fbox_portable(rows, rws, fo, fi, tmin_f, tfar_f, tn);
#else
            mask = fbox_portable(rows, rws, fo, fi, tmin_f, tfar_f, tn);
#endif
            if (fbox_descend(mask & n->nchild, tn, n->child, &code, stack_node, stack_t, &sp))
                continue;
        }
        /* pop the next entry that can still hold a closer hit */
        for (;;) {
            if (sp == 0)
                goto done;
            sp--;
            if (stack_t[sp] <= tfar_f)
                break;
        }
        code = stack_node[sp];
    }
done:
    if (best == UINT32_MAX)
        return 0;
    hit->t = closest;
    hit->prim = best;
    return 1;
}
