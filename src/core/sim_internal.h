/* The simulation object. Hot per-particle state is kept as separate aligned arrays (structure of
 * arrays); cold bookkeeping (parameters, ledger totals, names) lives beside it. src/core and the
 * integrators (src/integrators/) see this layout. */
#ifndef GR_SIM_INTERNAL_H
#define GR_SIM_INTERNAL_H

#include <math.h>
#include <stdint.h>

#include "granule/sim.h"
#include "models/law.h"

#ifdef _OPENMP
#include <omp.h>
/* the calling thread and the team size inside a parallel region (0 and 1 without OpenMP) */
#define GR_THREAD_ID omp_get_thread_num()
#define GR_THREAD_COUNT omp_get_num_threads()
#else
#define GR_THREAD_ID 0
#define GR_THREAD_COUNT 1
#endif

/* What one force evaluation reports besides the forces. */
typedef struct gr_force_report {
    double elastic;      /* sum k_s xi^2 / 2 over contacts, J */
    double power_normal; /* dissipation rates, W (>= 0) */
    double power_tangential;
    double power_friction;
    double lost;          /* energy a history law dropped without work (slip, ended contacts), J */
    int64_t new_contacts; /* pairs that came into overlap */
    double max_overlap;   /* largest xi / d */
    int worst_i, worst_j; /* the pair with max_overlap */
} gr_force_report;

/* The force kernel of a run (src/core/kernels.c): the instance that runs, and the laws it runs
 * (ids from models/list.h: nl the normal law, tl the tangential law or 0, rl the rolling law or 0;
 * clamp; rot = the spins take torques). */
typedef struct gr_kernel {
    void (*run)(gr_sim *s, gr_force_report *r);
    int dim, nl, tl, clamp, rot, rl;
} gr_kernel;

struct gr_sim {
    gr_sim_params params; /* the parameters it was created with */
    gr_contact_coeffs cc;
    int n, dim;
    double L, d, mass, dt;

    /* hot state, n entries each (y, vy, fy unused in 1D; z, vz, fz, gz only in 3D, NULL otherwise) */
    double *x, *y, *vx, *vy, *fx, *fy;
    double *gx, *gy; /* the non-conservative part of (fx, fy): everything but the springs k_s xi */
    double *z, *vz, *fz, *gz;
    double *noise; /* n * dim normals of the current step */
    /* Rotation (2D, only when cc.rotation): angular velocity, rad/s (counterclockwise), and the
     * torque of the last force evaluation, N m; moment of inertia q M r^2. NULL otherwise. */
    double *omega, *tq;
    /* 3D (spheres, only when cc.rotation): omega, tq and tg above are the z components of the
     * angular velocity, torque and its non-conservative part (a 2D disc spins about z), these the
     * x and y components (src/core/kernels_3d.c). NULL otherwise. */
    double *wx, *wy, *tqx, *tqy, *tgx, *tgy;
    /* rotation with a history law (models/list.h): the non-conservative part of tq, everything
     * but the springs' torques a k_t s, whose work the spin kicks must not book as dissipation
     * (their energy is the springs' k_t s^2 / 2); NULL otherwise (tq is then all non-conservative) */
    double *tg;
    double inertia;

    /* 2D neighbour finding: cell list feeding a half Verlet list in CSR form */
    double cutoff;         /* d (1 + skin) */
    double *x_ref, *y_ref; /* positions at the last rebuild */
    double *z_ref;         /* 3D (src/core/kernels_3d.c): z at the last rebuild */
    int ncell;             /* cells per side (3D: per edge of the cube); 0 = all pairs */
    int *cell_start, *cell_of, *cell_order;
    int *nl_start; /* n + 1 entries */
    int *nl_j;
    uint8_t *nl_contact; /* pair was in contact at the last force evaluation */
    int64_t nl_cap;
    /* The contact sublist (src/core/sublist.c): the entries p of the list whose pair is closer than
     * d (1 + sl_width) (or touching, or holding a history vector), row by row in list order,
     * rebuilt from the list when a particle has moved sl_width d / 2 since; the 2D and 3D
     * kernels scan it instead of the list when sl_on. The same pairs in the same order touch
     * either way, so every sum is the same. sl_verlet: the Verlet step runs this simulation (the
     * only kernels that read it); sl_list_at: the step of the list's last build; sl_screen: the
     * kernels pick the touching entries first (fewer than half of them touched at the build). */
    int *sl_start, *sl_p;
    int *sl_i, *sl_hits;   /* per kept entry: its row; the kernels' touching entries (scratch) */
    uint8_t *sl_flag;      /* per list entry: the build's decisions (3D: the screen's scratch) */
    int *sl_row, *sl_pref; /* per list entry: its row, the kept entries before it (one thread) */
    int sl_rows_ok;        /* sl_row holds the current list's rows */
    double sl_gap; /* the largest distance from the list's reference at the sublist's build */
    int64_t sl_cap, sl_list_at, sl_rebuilds;
    /* the width's adaptation (sublist.c, adapt_width): the entries scanned and the rebuilds' work
     * over the list's life, the kept entries and the step of the last build */
    int64_t sl_scan_work, sl_build_work, sl_built_at;
    int sl_kept;
    double sl_width;
    double *xs_ref, *ys_ref, *zs_ref;
    int sl_on, sl_verlet, sl_forced, sl_screen;

    /* 1D: pair (i, i+1 mod n) contact flags; the ring loop's per-pair scratch (3 n doubles) */
    uint8_t *pair_contact;
    double *ring_scratch;

    /* contact events (only when tracked) */
    uint16_t *contacts; /* contacts of each particle at the last force evaluation */
    uint16_t *contacts_now;
    gr_contact_event *events;
    int64_t n_events, cap_events;

    gr_kernel kernel;
    char kernel_name[160];

    /* Walls and gravity ([boundary], [gravity]; src/core/walls.c), chosen once: with walls_on = 0
     * (the periodic box) gr_forces runs the pair kernel alone, as ever. period[a] is the
     * neighbour list's period along axis a: L, or INFINITY across walls (no image pairs). */
    int walls_on;
    /* the laws against a wall (normal and tangential): reduced mass M (infinite partner), the
     * walls' own eps_n, eps_t, mu; wall_tl the tangential law's id (gr_kernel_tangential_id; 0:
     * none, or it does nothing) */
    gr_contact_coeffs wall_cc;
    int wall_tl;
    /* species lists with walls: each species' wall contact (nsp entries: the law prepared with
     * the grain's own mass, hertz's k_h scaled as for its own pair); NULL otherwise */
    gr_contact_coeffs *wall_cc_sp;
    double period[3];
    /* a history law at the walls: 4 slots per grain (its contacts with the walls at 0 and L of x,
     * then of y: slot 4 i + 2 a + side), NULL otherwise */
    double *wall_hist;
    /* the moving wall's work on the grains, J (gr_ledger.wall_work), and the normal impulse each
     * wall has taken from the grains since creation, N s (walls at 0 and L of x, then of y:
     * gr_sim_wall_impulse) */
    double wall_work;
    double wall_impulse[6];

    /* Species (src/core/species.c, docs/mixtures.md), only when params.n_species >= 2 (nsp = 0
     * otherwise: every array NULL, the monodisperse path as ever). d is then the largest contact
     * distance (cells, skin, placement), mass the mean mass. Per grain: its species, radius, mass
     * and 1 / mass; per species pair (a, b), a * nsp + b: the laws' coefficients prepared with
     * the pair's reduced mass (and radius), and the contact distance r_a + r_b. The kernel of a
     * run with species is the one of src/core/kernels_poly.c, the step that of
     * src/integrators/verlet/step_poly.c. */
    int nsp;
    int *species;
    double *rad, *mass_i, *inv_m;
    double *inertia_i; /* rotation with species: each grain's q m_i r_i^2 (NULL otherwise) */
    gr_contact_coeffs *cc_pair;
    double d_pair[GR_MAX_SPECIES * GR_MAX_SPECIES];
    /* a continuous radius distribution (params.size_distribution; nsp = 1, cc_pair NULL): each
     * pair's coefficients are cc's scaled to its reduced mass M and effective radius R from those
     * of the reference pair, cont_m12 and cont_r (kernels_poly.c) */
    double cont_m12, cont_r;

    /* bookkeeping */
    int64_t step;
    int64_t collisions, rebuilds;
    int64_t com_every; /* steps between centre-of-mass resets (com mode) */
    double elastic;    /* from the last force evaluation */
    double initial_energy;
    double injected, diss_n, diss_t, diss_f, removed_com;
    /* the driving, chosen once ([driving], granule/driving.h): the integrator's update and, for the
     * bath, its per-step factors and the energy its drag removed */
    gr_drive_update drive;
    gr_driving_coeffs drive_c;
    double diss_drag;
    double share[3]; /* fractions of the last step's dissipation by normal/tangential/friction */
    gr_force_report last;

    /* Threads (docs/performance.md, "Threads"). Every sum over particles or pairs is formed per
     * block of GR_BLOCK particles (rows of the pair list) and the blocks are combined in block
     * order, whatever the thread count; a thread owns whole blocks. */
    int nblk;                     /* ceil(n / GR_BLOCK) */
    struct gr_poly_par *poly_par; /* kernels_poly.c's state for threads (NULL until used) */
    double *blk;                  /* GR_BLK_FIELDS partial results per block */
    /* 2D and 3D forces with T > 1 threads (kernels.c, kernels_3d.c): thread t owns the rows (and the forces) of
     * particles [par_row[t], par_row[t+1]); a listed pair whose j lies outside the row owner's
     * range is a "cross" pair, added by the owner of j in list order (evaluated by it, or with a
     * history law computed first into pair_f), so every force is summed exactly as in the
     * one-thread scatter. */
    int par_threads;      /* T the cross lists were built for (0: not built) */
    int64_t par_rebuilds; /* s->rebuilds when they were built */
    int *par_row;         /* T + 1 */
    int *
        cross_start; /* T + 1: the cross pairs of thread t are k in [cross_start[t], cross_start[t+1]) */
    int *cross_p, *cross_i; /* list entry and row of cross pair k, ascending in p */
    int *in_start, *in_k; /* n + 1 / ncross: the cross pairs acting on particle j, ascending in k */
    int *in_list;         /* the particles with incoming cross pairs, ascending (at most ncross) */
    int *
        in_list_start; /* T + 1: those of thread t are in_list[in_list_start[t] .. in_list_start[t+1]) */
    double *pair_f;  /* 4 per cross pair: Fx, Fy, Gx, Gy on j (3D: 6, F then G) */
    double *pair_tq; /* rotation: the torque of each cross pair (3D: 3), NULL otherwise */
    double *pair_tg; /* its non-conservative part (with s->tg only) */
    int64_t cross_cap;

    /* the integrator (params.integrator, src/integrators/) and its own state (NULL for verlet) */
    const gr_integrator_type *integrator;
    void *integrator_state;

    /* contact history (src/core/contact_history.c): one slot per list entry, NULL unless the
     * tangential law keeps history; the non-zero slots saved by pair across a rebuild */
    double *nl_hist;
    int64_t *hist_start;
    int *hist_j;
    double *hist_v;
};

/* Block size of the fixed-order reductions (a multiple of the step's 8 lanes and of 2, so
 * blocks start on the same lane and noise pair as in one pass). Runs of up to GR_BLOCK particles
 * sum exactly as without blocks. */
#define GR_BLOCK 1024
#define GR_BLK_FIELDS 10

/* Threads to use for a 2D step or a 3D force evaluation of s: 1 in 1D, when there are fewer than
 * two blocks, or inside an enclosing parallel region; otherwise the gr_set_threads setting, at
 * most one per block. The results do not depend on it. */
int gr_team(const gr_sim *s);

/* src/core/placement.c: fill x, y for the scene's placement kind. */
int gr_place(gr_sim *s, gr_error *err);
/* Refuse overlapping positions (tolerance 1e-9 d); used for every initial state. */
int gr_check_overlaps(const gr_sim *s, gr_error *err);

/* src/core/sim.c: remove the centre-of-mass velocity (com noise mode); returns the kinetic
 * energy removed. */
double gr_remove_com(gr_sim *s);

/* src/core/events.c: per-particle contact transitions after a force evaluation */
int gr_events_update(gr_sim *s, gr_error *err);
/* Append one contact event to s->events (grown as needed). */
int gr_events_append(gr_sim *s, gr_contact_event ev, gr_error *err);

/* src/core/neighbours.c (3D: gr_neighbours_*_3d, which these call when dim = 3) */
int gr_neighbours_alloc(gr_sim *s, gr_error *err);
/* The contact sublist (sublist.c): after every build of the list, decide and build it; before a
 * force evaluation, rebuild it when a particle has moved half its skin (gr_sublist_refresh
 * measures the displacements; gr_sublist_refresh_moved takes the largest squared one, measured
 * by the caller against xs_ref, ys_ref, zs_ref, e.g. in the Verlet step's opening pass). */
void gr_sublist_after_build(gr_sim *s);
void gr_sublist_refresh(gr_sim *s);
void gr_sublist_refresh_moved(gr_sim *s, double moved2);
void gr_sublist_free(gr_sim *s);
/* With the sublist on: the largest squared displacement since the list's build if it may exceed
 * lim2, else 0 (the bound sl_gap + sqrt(moved2), moved2 the largest since the sublist's build, is
 * below it); the Verlet step's opening pass then measures the sublist's displacements only. */
double gr_sublist_list_moved2(const gr_sim *s, double moved2, double lim2);
int gr_neighbours_build(gr_sim *s, gr_error *err);

/* src/core/kernels_3d.c: spheres (docs/three-dimensions.md): the neighbour list and the force
 * kernel (the normal law of s->kernel) */
int gr_neighbours_alloc_3d(gr_sim *s, gr_error *err);
int gr_neighbours_build_3d(gr_sim *s, gr_error *err);

/* The list's rows built on T threads (neighbours.c): rows(s, r0, r1, b) appends the rows [r0,
 * r1) to the buffer b (gr_rows_append), setting nl_start[i] to each row's start in b; the
 * threads' buffers are then put one after the other into the list. A row depends only on its
 * particle, so the list is the one built in one pass whatever T. *count: the number of pairs. */
typedef struct gr_rows_buf {
    int *j;
    uint8_t *c;
    int64_t cap, count;
    int own;
} gr_rows_buf;
typedef int (*gr_list_rows)(gr_sim *s, int r0, int r1, gr_rows_buf *b);
int gr_neighbours_rows(gr_sim *s, int T, gr_list_rows rows, int64_t *count, gr_error *err);
/* Room in b for `need` entries; 0 when out of memory. */
int gr_rows_reserve(gr_sim *s, gr_rows_buf *b, int64_t need);
/* Room in the list for `need` entries (the contact history too: 3 doubles per entry in 3D). */
int gr_neighbours_grow(gr_sim *s, int64_t need, gr_error *err);
void gr_kernel_run_3d(gr_sim *s, gr_force_report *r);
/* the same loop with the tangential law (a 3D history vector per contact), rotation (angular
 * velocity vectors, torques) and the rolling law read from s->kernel */
void gr_kernel_run_3d_full(gr_sim *s, gr_force_report *r);
/* spring_dashpot + tangential_dashpot, unclamped, no rotation: the laws as constants */
void gr_kernel_run_3d_dashpots(gr_sim *s, gr_force_report *r);
/* src/core/kernels.c: the threads of a 2D or 3D force evaluation (gr_team), building the cross
 * lists (par_row, cross_*, in_*, pair_*) when the list or the thread count changed; 1 when they
 * cannot be built (out of memory) */
int gr_kernel_team(gr_sim *s);
/* The first (end = 0) or one past the last (end = 1) cross pair that thread tid of nth evaluates
 * in the first phase of a T-thread force evaluation: all T ranges' cross pairs shared evenly (the
 * rows before the last thread's hold them all when j > i, and the others would wait); which
 * thread evaluates a pair changes no bit. */
static inline int gr_cross_share(const gr_sim *s, const int T, const int tid, const int nth,
                                 const int end)
{
    return (int)((int64_t)s->cross_start[T] * (tid + end) / nth);
}

/* contact history: allocate the slots (zero), save them by pair before a rebuild, restore after */
int gr_history_enable(gr_sim *s, gr_error *err);
/* doubles per history slot: 1 (2D: s along t), 3 in 3D (the vector s) */
static inline int gr_history_width(const gr_sim *s) { return s->dim == 3 ? 3 : 1; }
int gr_history_save(gr_sim *s, gr_error *err);
void gr_history_restore(gr_sim *s);

/* src/core/species.c: species (docs/mixtures.md). Check what a run with species can do, assign
 * them and fill the per-grain arrays (before the placement; sets d to the largest contact
 * distance); the pair whose contact is shortest (its contact parameters and reduced mass, for
 * the time step); then every pair's coefficients at the step dt. */
int gr_species_setup(gr_sim *s, gr_error *err);
void gr_species_reference(gr_sim *s, gr_contact_params *p, double *m12);
int gr_species_coeffs(gr_sim *s, double dt, gr_error *err);
/* The walls' contact of each species (s->wall_cc_sp) from the walls' parameters wp at step dt. */
int gr_species_wall_coeffs(gr_sim *s, const gr_contact_params *wp, double dt, gr_error *err);
/* Grain i's radius: its own with species, d / 2 without. */
static inline double gr_grain_r(const gr_sim *s, int i) { return s->rad ? s->rad[i] : 0.5 * s->d; }
/* The contact distance of grains i and j: r_i + r_j with species, d without. */
static inline double gr_pair_d(const gr_sim *s, int i, int j)
{
    return s->rad ? s->rad[i] + s->rad[j] : s->d;
}
/* A radius distribution: the reference coefficients ref (prepared for the reduced mass m_ref and
 * effective radius r_ref) scaled to a contact of reduced mass M and effective radius R: the
 * stiffness as (R / r_ref)^(a - 1) for a force k xi^a (hertz: k_h ~ sqrt(R); the linear spring
 * alike for all), the damping as sqrt(M k) (a law calibrated to eps_n: the damping ratio depends
 * on eps_n alone), the elastic energy with the stiffness, the tangential laws' constants below
 * (kernels_poly.c's pairs, walls.c's
 * grains at a wall: M = m_i, R = r_i / 2 as for the grain's own pair). */
static inline void gr_size_scaled(const gr_contact_coeffs *ref, double m_ref, double r_ref,
                                  double M, double R, gr_contact_coeffs *c)
{
    const double sk = ref->pow_a == 1.0 ? 1.0 : pow(R / r_ref, ref->pow_a - 1.0);
    *c = *ref;
    c->k_s *= sk;
    c->gamma_n *= sqrt(M / m_ref * sk);
    c->e_scale *= sk;
    c->m12 = M;
    /* the tangential laws without history: the tangential mass with M (sliding_friction's limit,
     * rotation's q / (1 + q) kept); the dashpot's gamma_t = -m_t ln(eps_t) / t_c with the contact
     * time t_c ~ (M / k)^(1 / (a + 1)) at a given impact speed: gamma_t ~ M^(a / (a + 1))
     * k^(1 / (a + 1)) (sqrt(M k) for the linear spring), so every contact keeps eps_t */
    c->m_t *= M / m_ref;
    if (c->gamma_t != 0.0) {
        const double a = ref->pow_a;
        c->gamma_t *= a == 1.0 ? sqrt(M / m_ref * sk)
                               : pow(M / m_ref, a / (a + 1.0)) * pow(sk, 1.0 / (a + 1.0));
    }
}
/* src/core/kernels_poly.c: the force kernel of a run with species (1D ring, 2D or 3D list). */
void gr_kernel_run_poly(gr_sim *s, gr_force_report *r);
/* Free the threaded state of that kernel (records, incoming entries, block sums), if any. */
void gr_poly_par_free(gr_sim *s);

/* src/core/kernels.c: one force evaluation with the kernel chosen at creation (then the walls'
 * and gravity's pass when they are on) */
void gr_forces(gr_sim *s, gr_force_report *r);
/* The chosen kernel's normal law at one contact with coefficients c (overlap xi, normal relative
 * velocity g_n): returns f, sets *f_d (its non-conservative part) and *e (energy / e_scale). Not
 * on the pair loop's path: the walls' pass calls it per wall contact. */
double gr_kernel_normal(const gr_sim *s, const gr_contact_coeffs *c, double xi, double g_n,
                        double *f_d, double *e);

/* src/core/walls.c: flat walls and gravity (docs/systems-walls-gravity.md) */
/* Check and prepare them once, after the contact coefficients and the placement. */
int gr_walls_prepare(gr_sim *s, gr_error *err);
/* Add the wall contacts and gravity to the forces and the report of a pair-kernel evaluation. */
void gr_walls_forces(gr_sim *s, gr_force_report *r);
/* The potential energy in gravity, -M sum_i g . r_i, J (0 without gravity). */
double gr_walls_potential(const gr_sim *s);
/* The vibrating wall's motion at time t ([boundary] vibrate): its position *q and velocity *v,
 * A sin(2 pi f t), or for a sawtooth A (2 frac(f t + 1/2) - 1) at the speed 2 A f (walls.c; the
 * event integrator's moving wall, event_cells.h, uses the same function). */
void gr_walls_motion(const gr_sim_params *p, double t, double *q, double *v);
/* A tangential law at one contact outside the pair loops (the walls' pass): the law's id for
 * model m (0 when m is NULL), and the law itself by id (0: no force); *book is its ledger column
 * (GR_BOOK_TANGENTIAL, GR_BOOK_FRICTION), *history 1 for a law that keeps history. */
int gr_kernel_tangential_id(const gr_model *m);
int gr_kernel_tangential_history(int tl);
gr_tangential_force gr_kernel_tangential(int tl, const gr_contact_coeffs *c, gr_tangential_in in,
                                         int *book, int *history);
/* 3D (kernels_3d.c): a history law's vector step at one contact outside the pair loops (the
 * walls' pass), its ledger column in *book. */
gr_tangential_force3 gr_kernel_tangential3(int tl, const gr_contact_coeffs *c, gr_tangential_in3 in,
                                           int *book);
/* 1 when the chosen kernel's tangential law keeps a per-contact history (models/list.h). */
int gr_kernel_history(const gr_sim *s);
/* Brute-force O(N^2) reference forces (tests only). */
void gr_forces_bruteforce(const gr_sim *s, double *fx, double *fy, double *elastic);
/* Pick the kernel from the coefficients; sets s->kernel and s->kernel_name. */
int gr_kernel_choose(gr_sim *s, gr_error *err);
/* The number of compiled kernel instances (the hot list and one generic per dimension). */
int gr_kernel_instances(void);
/* 1 when s runs the generic instance of its dimension (its laws are not in the hot list). */
int gr_kernel_generic(const gr_sim *s);
/* Run s through the generic instance even if its laws are hot (tests: both give the same bits). */
int gr_kernel_force_generic(gr_sim *s);

#endif
