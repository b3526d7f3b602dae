/* world_traverse.h - the world's closest-hit traversal, included by
 * world_closest.c once per instruction set: it defines WTRAVERSE (the
 * function's name), with the AVX box test when WTRAV_AVX is 1, else the SSE2
 * one (when the build has SSE2 and the argument `simd` is 1) or the portable
 * one. With `anyhit` it returns 1 at the first item that replaces the hit
 * (*best_t, *best) it starts from (rt_world_occluded), else 0 when done.
 * Not a header to include anywhere else.
 *
 * The same walk as the spheres' tree (bvh_traverse.h): ordered depth-first,
 * the nearest child hit next, the others pushed far to near with their
 * entry distance, popped entries beyond the closest hit so far dropped; each
 * axis's box planes ordered by min and max (fbox.h's fbox_mm_*: nothing to
 * set up per ray, which for short bounces costs more than the two extra
 * operations a plane pair takes). The three box tests
 * do the same float operations in the same order, so they visit the same
 * leaves; the leaves' tests are in double (world_internal.h) and their rule
 * does not depend on the order, so every variant and brute force agree.
 * The any-hit walk takes the children in slot order, unsorted, and skips
 * the leaf of the shape whose hit (at *best_t, rt_world_shape_t's t) it
 * starts from: that test would compute the same t again and lose the tie
 * to itself, so it can never replace the hit. */

static inline __attribute__((always_inline)) int WTRAVERSE(const rt_world *w, const rt_ray *ray, double time,
                                                            double tmin, double *best_t, uint32_t *best,
                                                            const int simd, const int anyhit)
{
    const float tmin_f = near_bound(tmin);
    float tfar_f = far_bound(*best_t);
#if WTRAV_AVX
    (void)simd;
    fbox_mray8 vr;
    fbox_mray8_set(&vr, ray, tmin_f);
#else
    const float fo[3] = {(float)ray->orig.x, (float)ray->orig.y, (float)ray->orig.z};
    const float fi[3] = {safe_inv(ray->dir.x), safe_inv(ray->dir.y), safe_inv(ray->dir.z)};
#if RT_BVH_HAVE_SSE2
    const fbox_ray4 vr = {_mm_set1_ps(fo[0]), _mm_set1_ps(fo[1]), _mm_set1_ps(fo[2]), _mm_set1_ps(fi[0]),
                          _mm_set1_ps(fi[1]), _mm_set1_ps(fi[2]), _mm_set1_ps(tmin_f)};
#else
    (void)simd;
#endif
#endif
    int32_t stack_node[WSTACK];
    float stack_t[WSTACK];
    int sp = 0;
    int32_t code = 0;
    for (;;) {
        if (code < 0) {
            const int any = rt_world_test_item(w, ~(uint32_t)code, ray, time, tmin, best_t, best);
            if (any && anyhit)
                return 1;
            if (any)
                tfar_f = far_bound(*best_t);
        } else {
            const wide *n = &w->nodes[code];
            const float(*rows)[WWIDTH] = (const float(*)[WWIDTH])n->bmin;
            float tn[WWIDTH];
            int mask;
#if WTRAV_AVX
            mask = fbox_mm_avx(rows, &vr, tfar_f, tn);
#elif RT_BVH_HAVE_SSE2
            mask = simd ? fbox_mm_sse(rows, &vr, tfar_f, tn) : fbox_mm_portable(rows, fo, fi, tmin_f, tfar_f, tn);
#else
            mask = fbox_mm_portable(rows, fo, fi, tmin_f, tfar_f, tn);
#endif
            if (anyhit ? fbox_descend_any(mask & n->nchild, tn, n->child, ~(int32_t)*best, &code, stack_node, stack_t,
                                          &sp)
                       : fbox_descend(mask & n->nchild, tn, n->child, &code, stack_node, stack_t, &sp))
                continue;
        }
        for (;;) { /* pop the next entry that can still hold a closer hit */
            if (sp == 0)
                return 0;
            sp--;
            if (stack_t[sp] <= tfar_f)
                break;
        }
        code = stack_node[sp];
    }
}
