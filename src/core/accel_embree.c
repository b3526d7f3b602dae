/* accel_embree.c - Embree 3 as an alternative closest-hit intersector, for
 * side-by-side benchmarks against our BVH (built only with -DRT_EMBREE=ON,
 * which defines RT_HAVE_EMBREE). Owns: the Embree device and scene, the
 * translation of our double-precision spheres into Embree's float sphere
 * points, and the double-precision refinement of Embree's answer.
 *
 * Device. Debian's Embree uses TBB for its tasking. rtcNewDevice is given
 * "threads=1", which caps TBB's process-wide parallelism at 1: no TBB
 * worker is started while the device exists, the BVH build runs in the
 * calling thread, and no Embree thread competes with our OpenMP threads
 * while we render. (With the default config TBB starts cores-1 workers per
 * process - per MPI rank - at the first commit; they sleep afterwards, but
 * threads=1 avoids them altogether. At rtcReleaseDevice TBB starts one
 * worker, which sleeps at once.) rtcIntersect1 never uses Embree threads:
 * it runs in whichever OpenMP thread calls it, and many threads may call
 * it on the committed scene at once. Building the book's scenes takes
 * milliseconds single-threaded. We deliberately do not set the MXCSR to
 * flush-to-zero/denormals-are-zero as Embree's manual suggests: that mode
 * is per thread and would also change our double arithmetic, so the images.
 *
 * Scene. One RTC_GEOMETRY_TYPE_SPHERE_POINT geometry, vertex buffer
 * RTC_FORMAT_FLOAT4 = (x, y, z, |radius|), so primID == sphere index. A
 * negative radius (hollow sphere) has the same geometry; only shading flips
 * its normal. RTC_SCENE_FLAG_ROBUST makes Embree's traversal conservative,
 * like our BVH's widened boxes; it costs ~10 % against RTC_SCENE_FLAG_NONE
 * here, which gave the same answers on all our test rays.
 * RTC_BUILD_QUALITY_HIGH as the benchmark plan asks.
 *
 * Why t is recomputed. Embree intersects in float. For the ground sphere
 * (radius 1000, centre 1000 below the floor) its t is off by more than
 * 1e-4 in a quarter of the hits and by up to ~0.7 at far or grazing ones,
 * often more than the renderer's t_min (0.001): Embree's t would put hit
 * points below surfaces (acne, light leaks) and differ from the BVH's and
 * brute force's. So Embree only nominates the sphere; t comes from
 * rt_sphere_root in double, bit-identical to what the other
 * intersectors compute for that sphere. When the two disagree, the double
 * test decides:
 *  - double misses the nominated sphere entirely in (tmin, tmax) (grazing
 *    ray, or float's near root just above tmin where double's is just
 *    below and there is no far root in range): the candidate is dropped
 *    and Embree is asked again from just beyond its float t;
 *  - double hits the nominated sphere later than Embree's float t (beyond
 *    float rounding): something Embree ranked behind may in truth lie in
 *    between. Causes: the ground's float t is too early, or float took a
 *    near root that double rejects as <= tmin, so double took the far root
 *    (a sphere inside a glass shell would be in between). The hit is kept
 *    and Embree is asked again for the interval (float t, double t].
 * Each re-query starts strictly beyond the previous float t, so the loop
 * ends; it is also capped. On the book's final scene ~93 % of our test rays
 * need one rtcIntersect1, nearly all others two.
 *
 * What remains different from brute force: surfaces that float misses and
 * double hits, i.e. rays that barely dip into a sphere (secondary rays
 * leaving the ground at a grazing angle and re-entering it within ~0.4,
 * near-tangent rays re-entering their own small sphere just past tmin).
 * In our tests: ~4 in 100,000 secondary rays from surfaces, none in
 * 1,000,000 random, camera and ground-contact rays; each is a different
 * but plausible sample. Inflating the float radii to catch them would be
 * wrong: it moves exit (far) roots later, so a sphere the ray leaves could
 * be ranked behind another and never be nominated. */
#include "accel_embree.h"

#include <embree3/rtcore.h>
#include <math.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdlib.h>

#include "sphere.h"
#include "status.h"

/* Cap on rtcIntersect1 calls per ray; reached only in pathological cases
 * (1.25 M test rays on the final scene never needed more than 3). */
#define RT_EMBREE_MAX_QUERIES 8

typedef struct rt_embree {
    RTCDevice device;
    RTCScene scene;
    atomic_int first_error; /* first RTCError reported by the callback */
} rt_embree;

/* Records the first error; never prints (the module reports by status). */
static void on_error(void *user, enum RTCError code, const char *msg)
{
    (void)msg;
    rt_embree *e = user;
    int expected = RTC_ERROR_NONE;
    if (e && code != RTC_ERROR_NONE)
        atomic_compare_exchange_strong(&e->first_error, &expected, (int)code);
}

static int status_of(int code)
{
    switch (code) {
    case RTC_ERROR_NONE:
        return RT_OK;
    case RTC_ERROR_OUT_OF_MEMORY:
        return RT_ENOMEM;
    case RTC_ERROR_INVALID_ARGUMENT:
    case RTC_ERROR_INVALID_OPERATION:
        return RT_EINVAL;
    default: /* UNSUPPORTED_CPU, UNKNOWN, CANCELLED */
        return RT_EUNSUPPORTED;
    }
}

/* Status of the most recent Embree calls: the callback's record, else the
 * device's own error state (which also catches errors from calls made
 * before the callback was installed). */
static int check(rt_embree *e)
{
    int code = atomic_load(&e->first_error);
    if (code == RTC_ERROR_NONE)
        code = (int)rtcGetDeviceError(e->device);
    return status_of(code);
}

void rt_embree_free(void *p)
{
    rt_embree *e = p;
    if (!e)
        return;
    if (e->scene)
        rtcReleaseScene(e->scene);
    if (e->device)
        rtcReleaseDevice(e->device);
    free(e);
}

int rt_embree_build(void **out, const rt_scene *s)
{
    *out = NULL;
    rt_embree *e = calloc(1, sizeof *e);
    if (!e)
        return RT_ENOMEM;
    atomic_init(&e->first_error, RTC_ERROR_NONE);

    e->device = rtcNewDevice("threads=1");
    if (!e->device) {
        int st = status_of((int)rtcGetDeviceError(NULL));
        free(e);
        return st ? st : RT_EUNSUPPORTED;
    }
    rtcSetDeviceErrorFunction(e->device, on_error, e);
    if (!rtcGetDeviceProperty(e->device, RTC_DEVICE_PROPERTY_POINT_GEOMETRY_SUPPORTED)) {
        rt_embree_free(e);
        return RT_EUNSUPPORTED;
    }

    int st = RT_OK;
    e->scene = rtcNewScene(e->device);
    if (!e->scene) {
        st = check(e);
        goto fail;
    }
    rtcSetSceneFlags(e->scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(e->scene, RTC_BUILD_QUALITY_HIGH);

    if (s->n_spheres > 0) {
        RTCGeometry g = rtcNewGeometry(e->device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
        if (!g) {
            st = check(e);
            goto fail;
        }
        float *v = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                           4 * sizeof(float), s->n_spheres);
        if (!v) {
            st = check(e);
            rtcReleaseGeometry(g);
            goto fail;
        }
        for (uint32_t i = 0; i < s->n_spheres; i++) {
            const rt_sphere *sp = &s->spheres[i];
            v[4 * (size_t)i + 0] = (float)sp->center.x;
            v[4 * (size_t)i + 1] = (float)sp->center.y;
            v[4 * (size_t)i + 2] = (float)sp->center.z;
            v[4 * (size_t)i + 3] = (float)fabs(sp->radius);
        }
        rtcCommitGeometry(g);
        rtcAttachGeometryByID(e->scene, g, 0);
        rtcReleaseGeometry(g); /* the scene holds its own reference */
    }
    rtcCommitScene(e->scene);
    st = check(e);
    if (st)
        goto fail;
    *out = e;
    return RT_OK;

fail:
    rt_embree_free(e);
    return st ? st : RT_EUNSUPPORTED;
}

/* Conservative double -> float: the float interval [down(tmin), up(tmax)]
 * contains (tmin, tmax), so rounding never makes Embree skip a sphere the
 * double test would accept. */
static inline float f_down(double x)
{
    float f = (float)x;
    return (double)f > x ? nextafterf(f, -INFINITY) : f;
}
static inline float f_up(double x)
{
    float f = (float)x;
    return (double)f < x ? nextafterf(f, INFINITY) : f;
}

/* Whether Embree's float t can be trusted as a lower bound for everything
 * else: our double t is not later than it beyond float rounding. */
static inline int not_later(double t, float tf)
{
    return t <= (double)tf + 1e-5 * fabs((double)tf);
}

int rt_embree_closest(const void *p, const rt_scene *s, const rt_ray *ray, double tmin, double tmax,
                      rt_hit *hit)
{
    const rt_embree *e = p;
    const double a = rt_v3_len2(ray->dir);
    double best_t = tmax;
    uint32_t best = UINT32_MAX;
    float lo = f_down(tmin > 0.0 ? tmin : 0.0); /* Embree requires tnear >= 0 */

    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);

    for (int q = 0; q < RT_EMBREE_MAX_QUERIES; q++) {
        float hi = f_up(best_t);
        if (!(lo <= hi))
            break;
        struct RTCRayHit rh;
        rh.ray.org_x = (float)ray->orig.x;
        rh.ray.org_y = (float)ray->orig.y;
        rh.ray.org_z = (float)ray->orig.z;
        rh.ray.tnear = lo;
        rh.ray.dir_x = (float)ray->dir.x;
        rh.ray.dir_y = (float)ray->dir.y;
        rh.ray.dir_z = (float)ray->dir.z;
        rh.ray.time = 0.0f;
        rh.ray.tfar = hi;
        rh.ray.mask = UINT32_MAX;
        rh.ray.id = 0;
        rh.ray.flags = 0;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(e->scene, &ctx, &rh);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID)
            break;
        const uint32_t prim = rh.hit.primID;
        const float tf = rh.ray.tfar;
        if (prim == best || prim >= s->n_spheres)
            break; /* back at the kept candidate (its far root): done */
        const rt_sphere *sp = &s->spheres[prim];
        if (rt_sphere_closer(sp->center, sp->radius * sp->radius, prim, ray, a, tmin, &best_t, &best) &&
            not_later(best_t, tf))
            break;
        lo = nextafterf(tf, INFINITY);
    }
    if (best == UINT32_MAX)
        return 0;
    hit->t = best_t;
    hit->prim = best;
    return 1;
}
