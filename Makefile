# dolfinx_seal -- the two commands of the README, plus developer targets.
# Both provision the DOLFINx environment on first use (scripts/dx).
DX ?= scripts/dx
NP ?= 2
NP3 ?= 3
XDIST ?= 2
PYTEST_FLAGS ?= -q -p no:cacheprovider

.PHONY: demo demo-ball demo-sector test test-dx-paths test-serial test-mpi test-mpi3 test-mpi3-all test-slow lint bench bench-perf bench-point soak stability env

demo:  ## the main demo: the lubricated lip seal (installed section, leakage line, torque curve) into results/demo
	$(DX) mpirun -n $(NP) python3 demos/lip_seal.py --out results/demo

demo-sector:  ## S0's two-scale lip seal on a periodic 3D sector: maps at rest, cavitation against speed (results/demo-sector)
	$(DX) mpirun -n $(NP) python3 demos/lip_sector.py --out results/demo-sector

demo-ball:  ## the former main demo: a short ball Stribeck sweep (writes into results/demo-ball)
	$(DX) mpirun -n $(NP) python3 demos/ball_stribeck.py --out results/demo-ball

# the 3-rank run in `make test`: the solver, constraint, mesh and fault tests, where
# odd partitions matter (about a minute); `make test-mpi3-all` runs the whole suite
MPI3_TESTS ?= tests/test_snes.py tests/test_meshing.py tests/test_fault_injection.py tests/test_chains.py \
	tests/verification/test_periodic_vi.py tests/verification/test_obstacle_2d.py \
	tests/verification/test_reynolds_rigid.py tests/verification/test_film_cavitation.py \
	tests/test_projected_mpc.py tests/unit/test_film_upwinding.py

test: test-dx-paths test-serial test-mpi test-mpi3  ## the suite serially (on $(XDIST) workers) and under mpirun -n $(NP); its MPI core under -n $(NP3)

test-dx-paths:  ## on the host: scripts/dx sees the caller's cwd, $HOME, /tmp and path arguments
	bash tests/test_dx_paths.sh

test-serial:  ## one rank; pytest-xdist spreads the tests over $(XDIST) processes (XDIST=0: none)
	$(DX) python3 -m pytest $(PYTEST_FLAGS) $(if $(filter-out 0,$(XDIST)),-n $(XDIST))

test-mpi:
	$(DX) mpirun -n $(NP) python3 -m mpi4py -m pytest $(PYTEST_FLAGS)

test-mpi3:  ## $(MPI3_TESTS) on 3 ranks, oversubscribed on a 2-core machine on purpose (odd partitions, a rank with little work)
	$(DX) mpirun -n $(NP3) --map-by :OVERSUBSCRIBE python3 -m mpi4py -m pytest $(PYTEST_FLAGS) $(MPI3_TESTS)

test-mpi3-all:  ## the whole suite on 3 ranks (about an hour on 2 cores)
	$(DX) mpirun -n $(NP3) --map-by :OVERSUBSCRIBE python3 -m mpi4py -m pytest $(PYTEST_FLAGS)

test-slow:  ## heavier verification cases (not in CI's default suite)
	$(DX) python3 -m pytest $(PYTEST_FLAGS) -m slow

lint:  ## ruff on the host (no DOLFINx needed), from a small tools venv in the cache (scripts/tool)
	scripts/tool ruff format --check . && scripts/tool ruff check .

bench:  ## benchmarks write into bench/results/
	$(DX) python3 bench/reynolds_scaling.py
	$(DX) python3 bench/coupled_vs_partitioned.py
	$(DX) python3 bench/cylinder_newton_vs_mesh.py
	$(DX) python3 bench/cylinder_half_space_reference.py
	$(DX) python3 bench/ball_similar_meshes.py
	$(DX) python3 bench/ball_hamrock_dowson.py
	$(DX) python3 bench/ball_stribeck_roughness.py
	$(DX) python3 bench/ball_low_speed.py
	$(DX) python3 bench/ball_extremes.py
	$(DX) python3 bench/lip_mesh.py
	$(DX) python3 bench/lip_extremes.py
	$(DX) python3 bench/rough_band.py

# the solver before issue 18 (a new reduced submatrix and MUMPS analysis every Newton
# step, the secant predictor, no Newton cap or stall rule): the reference row
PERF_BEFORE = --solver vi_linear_solve=submatrix --set stepping.tangent=false \
	--set stepping.max_newton=0 --set stepping.stall_steps=0
# film maps of every PERF_FILES-th speed (about 1 s each on rank 0; 1: every speed)
PERF_FILES ?= 10
PERF_REF = --reference bench/results/perf/before/sweep.csv --point-files $(PERF_FILES)

bench-perf:  ## issue 18, about 40 min: the 30-speed ball Stribeck sweep with the solver before issue 18 on $(NP) ranks, then today's on 1 rank, on $(NP) ranks, and as $(NP) one-rank chains, each compared with the first; the cylinder point in linear-elastic solves (bench/results/perf/perf.csv, coupled_vs_partitioned.csv)
	$(DX) mpirun -n $(NP) python3 bench/perf.py --chains 1 --label before $(PERF_BEFORE) --point-files 0
	$(DX) python3 bench/perf.py --chains 1 $(PERF_REF)
	$(DX) mpirun -n $(NP) python3 bench/perf.py --chains 1 $(PERF_REF)
	$(DX) mpirun -n $(NP) python3 bench/perf.py --chains $(NP) $(PERF_REF)
	$(DX) python3 bench/coupled_vs_partitioned.py --tangent --relaxations 1 --budget 20 --out bench/results/perf

bench-point:  ## issue 18: one ball point at a/20 (1 m/s, from its start) on 1 and on $(NP) ranks (bench/results/perf/perf.csv)
	$(DX) python3 bench/perf.py --points 1 --per-a 20 --label "point a/20, 1 rank"
	$(DX) mpirun -n $(NP) python3 bench/perf.py --points 1 --per-a 20 --label "point a/20, $(NP) ranks"

soak:  ## about 10 min: memory (C heap trimmed before each reading) over a 240-point cylinder sweep, serial and on $(NP) ranks (bench/results/soak*_trim.csv, .png)
	$(DX) python3 bench/soak.py --trim
	$(DX) mpirun -n $(NP) python3 bench/soak.py --trim

STABILITY ?= cylinder lip-install lip ball lip-static lip-dynamic

stability:  ## long (hours: the first four tables about an hour and a half on 2 cores, the two sector tables 50 and 58 min at one rank): the stiff and extreme cases of studies/stability/ (results/stability/SCENE/)
	for s in $(STABILITY); do $(DX) mpirun -n $(NP) python3 -m dolfinx_seal.cli study stability $$s || exit $$?; done

env:  ## provision only
	$(DX) python3 -c "import dolfinx; print('DOLFINx', dolfinx.__version__)"
