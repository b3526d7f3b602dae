/* accel_embree.h - Embree 3 as an alternative intersector (benchmarks only;
 * compiled when CMake is configured with -DRT_EMBREE=ON). */
#ifndef RT_ACCEL_EMBREE_H
#define RT_ACCEL_EMBREE_H

#include "accel.h"
#include "scene.h"

/* Builds an Embree device + scene of RTC_GEOMETRY_TYPE_SPHERE_POINT
 * primitives (one per sphere, primID == sphere index). */
int rt_embree_build(void **out, const rt_scene *s);
void rt_embree_free(void *e);
/* Closest hit via rtcIntersect1; t is then recomputed in double with
 * rt_sphere_root on the sphere Embree found, so shading sees the same
 * precision as with the other intersectors. */
int rt_embree_closest(const void *e, const rt_scene *s, const rt_ray *ray, double tmin, double tmax,
                      rt_hit *hit);

#endif
