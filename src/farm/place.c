/* place.c - where a rank's threads run: the CPUs of its affinity mask (or
 * OpenMP's places), how many ranks of its node share that very mask, the
 * default thread count, and binding threads one to a CPU. */
#define _GNU_SOURCE
#include "internal.h"

#include <pthread.h>
#include <sched.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#ifdef RT_HAVE_MPI
#include <mpi.h>
#endif

/* The CPUs this rank may run threads on, and how many threads fit there.
 * With OpenMP thread binding on (OMP_PROC_BIND), the runtime has already
 * pinned this thread to the first of its places when main starts, so the
 * affinity mask shows one core: the places say where the team will run,
 * one thread per place. */
static int affinity(cpu_set_t *set, int *bound)
{
    CPU_ZERO(set);
    *bound = 0;
#ifdef _OPENMP
    int places = omp_get_num_places();
    if (omp_get_proc_bind() != omp_proc_bind_false && places > 0) {
        for (int p = 0; p < places; p++) {
            int n = omp_get_place_num_procs(p);
            int *ids = n > 0 ? malloc((size_t)n * sizeof *ids) : NULL;
            if (ids) {
                omp_get_place_proc_ids(p, ids);
                for (int i = 0; i < n; i++)
                    if (ids[i] >= 0 && ids[i] < CPU_SETSIZE)
                        CPU_SET(ids[i], set);
            }
            free(ids);
        }
        if (CPU_COUNT(set) > 0) {
            *bound = 1;
            return places;
        }
        CPU_ZERO(set);
    }
#endif
    if (sched_getaffinity(0, sizeof *set, set) == 0 && CPU_COUNT(set) > 0)
        return CPU_COUNT(set);
    long online = sysconf(_SC_NPROCESSORS_ONLN);
    return online > 0 ? (int)online : 1;
}

void rt_farm_place_init(rt_farm *f)
{
    cpu_set_t mask;
    f->cores = affinity(&mask, &f->omp_bound);
}

void rt_farm_place_share(rt_farm *f)
{
#ifdef RT_HAVE_MPI
    cpu_set_t mask;
    int bound;
    affinity(&mask, &bound);
    /* Which ranks of this node run on exactly the same CPUs? */
    MPI_Comm node;
    if (MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, f->rank, MPI_INFO_NULL, &node) == MPI_SUCCESS) {
        int lrank = 0, lsize = 1;
        MPI_Comm_rank(node, &lrank);
        MPI_Comm_size(node, &lsize);
        cpu_set_t *all = malloc((size_t)lsize * sizeof *all);
        if (all && MPI_Allgather(&mask, (int)sizeof mask, MPI_BYTE, all, (int)sizeof mask, MPI_BYTE, node) ==
                       MPI_SUCCESS) {
            f->mask_share = 0;
            for (int r = 0; r < lsize; r++) {
                if (CPU_EQUAL(&all[r], &mask)) {
                    if (r < lrank)
                        f->mask_index++;
                    f->mask_share++;
                }
            }
        }
        free(all);
        MPI_Comm_free(&node);
    }
#else
    (void)f;
#endif
}

int rt_farm_default_threads(const rt_farm *f)
{
    int share = f->mask_share > 0 ? f->mask_share : 1;
    int n = f->cores / share + (f->mask_index < f->cores % share ? 1 : 0);
    return n > 0 ? n : 1;
}

int rt_farm_bind_threads(const rt_farm *f, int threads)
{
    const char *env = getenv("RT_BIND");
    if (f->omp_bound || getenv("OMP_PROC_BIND") || (env && !strcmp(env, "0")))
        return 0;
    /* affinity() read this mask at rt_farm_init; nothing has changed it */
    cpu_set_t mask;
    if (sched_getaffinity(0, sizeof mask, &mask) != 0 || (long)threads * f->mask_share != CPU_COUNT(&mask))
        return 0;
    /* this rank's CPUs: the mask's CPUs [first, first + threads) */
    const int first = f->mask_index * threads;
    int cpu[CPU_SETSIZE], n = 0;
    for (int c = 0; c < CPU_SETSIZE; c++)
        if (CPU_ISSET(c, &mask)) {
            if (n >= first && n < first + threads)
                cpu[n - first] = c;
            n++;
        }
    int bound = 0;
#ifdef _OPENMP
#pragma omp parallel num_threads(threads) reduction(+ : bound)
    {
        const int k = omp_get_thread_num();
        cpu_set_t one;
        CPU_ZERO(&one);
        CPU_SET(cpu[k], &one);
        bound += omp_get_num_threads() == threads && pthread_setaffinity_np(pthread_self(), sizeof one, &one) == 0;
    }
#else
    (void)cpu;
#endif
    return bound == threads;
}

