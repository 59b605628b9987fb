! The thin layer f2py reads: plain subroutines with C kinds, everything else delegated to
! the core modules. Names (parameters, controls, counters) travel as comma-separated
! strings and are matched by the core's registry, so adding a law, a method or a counter
! changes nothing here. Never call these directly: the Python facade (stickslip/core.py)
! validates input and raises on bad status.

!> The registry as text (stickslip_registry's registry_text), NUL-padded.
subroutine registry(text)
    use stickslip_registry, only: registry_text
    implicit none
    character(len=32768), intent(out) :: text
    text = registry_text()
end subroutine registry

!> The library's message for a status code.
subroutine message(status, msg)
    use, intrinsic :: iso_c_binding, only: c_int
    use stickslip_registry, only: stickslip_message
    implicit none
    integer(c_int), intent(in) :: status
    character(len=400), intent(out) :: msg
    msg = stickslip_message(status)
end subroutine message

!> Friction coefficient mu(v) [-] of law `law` at n velocities [m/s], with the named
!! parameters pkeys = 'name,name,...' valued by pvals (the others at their defaults).
subroutine friction(law, pkeys, pvals, np, v, n, mu, status)
    use, intrinsic :: iso_c_binding, only: c_int, c_double
    use stickslip_kinds, only: SS_OK
    use stickslip_params, only: param_values
    use stickslip_friction, only: friction_law
    use stickslip_registry, only: make_law, split_names
    implicit none
    integer(c_int), intent(in) :: law
    character(len=*), intent(in) :: pkeys
    integer(c_int), intent(in) :: np
    real(c_double), intent(in) :: pvals(np)
    !f2py integer intent(hide), depend(pvals) :: np = len(pvals)
    integer(c_int), intent(in) :: n
    real(c_double), intent(in) :: v(n)
    !f2py integer intent(hide), depend(v) :: n = len(v)
    real(c_double), intent(out) :: mu(n)
    integer(c_int), intent(out) :: status
    class(friction_law), allocatable :: fl
    type(param_values) :: p
    mu = 0.0_c_double
    status = make_law(law, split_names(pkeys), pvals, fl, p)
    if (status == SS_OK) mu = fl%mu(v)
end subroutine friction

!> Simulate a scene from y0 at t = 0 to t_end. Names travel in one string, keys = 'pkeys|ckeys'
!! (physical parameters, then controls), their values and the state in one array,
!! vals = [pvals(np), y0(n), rtol(nrt), atol(nat), cvals]: one array and one string to convert
!! per call instead of five and two. t_out: requested times (grid mode) or room for every step
!! (overwritten with step times). stats(ni + nr + npar) receives the integer counters, the real
!! counters named by the registry's 'stats' record, then every parameter as resolved (registry
!! order); the caller gives the sizes, which must match the registry's. events(4, nev): room for
!! event_driven's events (t, kind, position, contact), nev = 0 for other methods. stop(1) and
!! cpu: as for run_prepared. prepare_run and run_prepared are this call in two parts, for a
!! setting run many times.
subroutine run_simulation(scene, law, method, keys, vals, nv, np, n, nrt, nat, t_end, &
                          nrow, t_out, y_out, ni, nr, npar, nst, stats, stop, events, nev, status, cpu)
    use, intrinsic :: iso_c_binding, only: c_int, c_double
    use stickslip_kinds, only: SS_OK, SS_BAD_DIM
    use stickslip_simulate, only: prepared_simulation
    use stickslip_wrap_interrupt, only: prepare_setting, timed_run
    implicit none
    integer(c_int), intent(in) :: scene, law, method
    character(len=*), intent(in) :: keys
    integer(c_int), intent(in) :: nv, np, n, nrt, nat, nrow, ni, nr, npar, nst
    real(c_double), intent(in) :: vals(nv)
    !f2py integer intent(hide), depend(vals) :: nv = len(vals)
    real(c_double), intent(in) :: t_end
    real(c_double), intent(inout) :: t_out(nrow)
    !f2py integer intent(hide), depend(t_out) :: nrow = len(t_out)
    real(c_double), intent(out) :: y_out(n, nrow)
    !f2py integer intent(hide), depend(ni, nr, npar) :: nst = ni + nr + npar
    real(c_double), intent(out) :: stats(nst)
    integer(c_int), intent(inout) :: stop(1)
    integer(c_int), intent(in) :: nev
    real(c_double), intent(inout) :: events(4, nev)
    !f2py integer intent(hide), depend(events) :: nev = shape(events, 1)
    integer(c_int), intent(out) :: status
    real(c_double), intent(out) :: cpu
    !f2py threadsafe
    type(prepared_simulation) :: prep
    real(c_double) :: resolved(npar)
    y_out = 0.0_c_double
    stats = 0.0_c_double
    cpu = 0.0_c_double
    call prepare_setting(scene, law, method, keys, vals, np, n, nrt, nat, t_end, prep, resolved, status)
    if (status /= SS_OK .or. ni < 0 .or. nr < 0) then
        if (status == SS_OK) status = SS_BAD_DIM
        return
    end if
    call timed_run(prep, t_out, y_out, stop(1), events, stats(1:ni + nr), status, cpu)
    stats(ni + nr + 1:) = resolved
end subroutine run_simulation

!> The first part of run_simulation (same arguments up to t_end): build the setting once (the
!! scene with its law and the method's options), for run_prepared to run as often as asked,
!! from any thread. handle: the setting's address (0 on bad input), to be given to run_prepared
!! and, once no run needs it, to free_prepared. resolved(npar): every parameter as resolved
!! (registry order; npar must match the registry's). status: SS_OK or the bad input's code.
subroutine prepare_run(scene, law, method, keys, vals, nv, np, n, nrt, nat, t_end, npar, resolved, &
                       handle, status)
    use, intrinsic :: iso_c_binding, only: c_int, c_int64_t, c_double, c_loc
    use stickslip_kinds, only: SS_OK
    use stickslip_simulate, only: prepared_simulation
    use stickslip_wrap_interrupt, only: prepare_setting
    implicit none
    integer(c_int), intent(in) :: scene, law, method
    character(len=*), intent(in) :: keys
    integer(c_int), intent(in) :: nv, np, n, nrt, nat, npar
    real(c_double), intent(in) :: vals(nv)
    !f2py integer intent(hide), depend(vals) :: nv = len(vals)
    real(c_double), intent(in) :: t_end
    real(c_double), intent(out) :: resolved(npar)
    integer(c_int64_t), intent(out) :: handle
    integer(c_int), intent(out) :: status
    type(prepared_simulation), pointer :: prep
    handle = 0
    allocate(prep)
    call prepare_setting(scene, law, method, keys, vals, np, n, nrt, nat, t_end, prep, resolved, status)
    if (status /= SS_OK) then
        deallocate(prep)
        return
    end if
    handle = transfer(c_loc(prep), handle)
end subroutine prepare_run

!> Run a setting of prepare_run or prepare_model_run: output, counters and status as
!! run_simulation's, stats(nst) without the resolved parameters (nst = ni + nr, the registry's
!! counts), y_out(n, nrow) with n the setting's output state size (a model's: every body's
!! state, its driven ones' too), drive_force(nd, nrow) each drive's force [N] (nd: the
!! model's drives, 0 for a setting without). stop(1) on entry: -1 a long run on the main
!! thread (arm the SIGINT handler), -2 a long run elsewhere, 0 a run too short for the
!! integrators to look at the flag. cpu: the run's time [s], the process's CPU time for a long
!! run, the monotonic wall time for a short one (two reads of the CPU clock are system calls
!! that cost more than such a run). SS_BAD_DIM for handle 0 or sizes that are not the setting's.
subroutine run_prepared(handle, nrow, t_out, n, y_out, nst, stats, stop, events, nev, status, cpu, nd, drive_force)
    use, intrinsic :: iso_c_binding, only: c_int, c_int64_t, c_double, c_ptr, c_null_ptr, c_f_pointer
    use stickslip_kinds, only: SS_BAD_DIM
    use stickslip_simulate, only: prepared_simulation, prepared_sizes
    use stickslip_wrap_interrupt, only: timed_run
    implicit none
    integer(c_int64_t), intent(in) :: handle
    integer(c_int), intent(in) :: nrow, n, nst, nev, nd
    real(c_double), intent(inout) :: t_out(nrow)
    !f2py integer intent(hide), depend(t_out) :: nrow = len(t_out)
    real(c_double), intent(out) :: y_out(n, nrow)
    real(c_double), intent(out) :: stats(nst)
    integer(c_int), intent(inout) :: stop(1)
    real(c_double), intent(inout) :: events(4, nev)
    !f2py integer intent(hide), depend(events) :: nev = shape(events, 1)
    integer(c_int), intent(out) :: status
    real(c_double), intent(out) :: cpu
    !f2py integer optional, intent(in) :: nd = 0
    real(c_double), intent(out) :: drive_force(nd, nrow)
    !f2py threadsafe
    type(prepared_simulation), pointer :: prep
    type(c_ptr) :: address
    integer :: n_prep, nd_prep
    y_out = 0.0_c_double
    stats = 0.0_c_double
    drive_force = 0.0_c_double
    cpu = 0.0_c_double
    status = SS_BAD_DIM
    if (handle == 0) return
    address = transfer(handle, c_null_ptr)
    call c_f_pointer(address, prep)
    call prepared_sizes(prep, n_prep, nd_prep)
    if (n /= n_prep .or. nd /= nd_prep) return
    call timed_run(prep, t_out, y_out, stop(1), events, stats, status, cpu, drive_force)
end subroutine run_prepared

!> prepare_run for a model given as arrays, one per kind of element (body indices as reals,
!! from 1, 0 the ground; one array per kind so that f2py sees each size once): bodies(3, nb) =
!! (mass, x0, v0), springs(4, ns) = (a, b, k, rest length), dampers(3, nd) = (a, b, c),
!! forces(2, nf) = (body, signal), contacts(5, nc) = (a, b, law code, normal-force signal,
!! surface-velocity signal or 0), their law parameters (names pkeys, values pvals; contact i's
!! from con_ptr(i) to con_ptr(i+1)-1), signals(5, nop) = (operation, its 4 arguments) with
!! sig_start and tables(2, ntab) = (t, value) (stickslip_signal), drives(3, ndr) = (body,
!! kind, signal). The model is built from its arrays once, specialised (`build_run`), with the
!! method named `method`, its controls and the run (y0: every body's x, v, then the law
!! states; rtol, atol, t_end), for run_prepared to run (a model with drives: its free bodies,
!! the driven ones' states and each drive's force from the signals) and free_prepared to
!! release, as a scene's setting. handle: 0 on bad input; status: SS_OK or the bad input's
!! code, with (elem_kind, elem_index) naming a bad element.
subroutine prepare_model_run(bodies, nb, springs, ns, dampers, nd, forces, nf, contacts, nc, con_ptr, ncp, &
                             pkeys, pvals, npv, signals, nop, sig_start, nss, tables, ntab, drives, ndr, &
                             method, y0, n, t_end, rtol, nrt, atol, nat, ckeys, cvals, ncv, slip_size, &
                             handle, status, elem_kind, elem_index)
    use, intrinsic :: iso_c_binding, only: c_int, c_int64_t, c_double, c_loc
    use stickslip_kinds, only: SS_OK, SS_BAD_DIM, SS_BAD_METHOD
    use stickslip_params, only: NAME_LEN
    use stickslip_registry, only: split_names, code_of, new_controls
    use stickslip_model_system, only: model_system
    use stickslip_simulate, only: prepared_simulation
    use stickslip_user_model, only: stickslip_model, model_from_arrays, drive_plan, control_step
    implicit none
    integer(c_int), intent(in) :: nb, ns, nd, nf, nc, ncp, npv, nop, nss, ntab, ndr, n, nrt, nat, ncv
    real(c_double), intent(in) :: bodies(3, nb)
    !f2py integer intent(hide), depend(bodies) :: nb = shape(bodies, 1)
    real(c_double), intent(in) :: springs(4, ns)
    !f2py integer intent(hide), depend(springs) :: ns = shape(springs, 1)
    real(c_double), intent(in) :: dampers(3, nd)
    !f2py integer intent(hide), depend(dampers) :: nd = shape(dampers, 1)
    real(c_double), intent(in) :: forces(2, nf)
    !f2py integer intent(hide), depend(forces) :: nf = shape(forces, 1)
    real(c_double), intent(in) :: contacts(5, nc)
    !f2py integer intent(hide), depend(contacts) :: nc = shape(contacts, 1)
    integer(c_int), intent(in) :: con_ptr(ncp)
    !f2py integer intent(hide), depend(con_ptr) :: ncp = len(con_ptr)
    character(len=*), intent(in) :: pkeys, ckeys, method
    real(c_double), intent(in) :: pvals(npv)
    !f2py integer intent(hide), depend(pvals) :: npv = len(pvals)
    real(c_double), intent(in) :: signals(5, nop)
    !f2py integer intent(hide), depend(signals) :: nop = shape(signals, 1)
    integer(c_int), intent(in) :: sig_start(nss)
    !f2py integer intent(hide), depend(sig_start) :: nss = len(sig_start)
    real(c_double), intent(in) :: tables(2, ntab)
    !f2py integer intent(hide), depend(tables) :: ntab = shape(tables, 1)
    real(c_double), intent(in) :: drives(3, ndr)
    !f2py integer intent(hide), depend(drives) :: ndr = shape(drives, 1)
    real(c_double), intent(in) :: y0(n)
    !f2py integer intent(hide), depend(y0) :: n = len(y0)
    real(c_double), intent(in) :: t_end
    real(c_double), intent(in) :: rtol(nrt)
    !f2py integer intent(hide), depend(rtol) :: nrt = len(rtol)
    real(c_double), intent(in) :: atol(nat)
    !f2py integer intent(hide), depend(atol) :: nat = len(atol)
    real(c_double), intent(in) :: cvals(ncv)
    !f2py integer intent(hide), depend(cvals) :: ncv = len(cvals)
    !> 1: the adaptive methods' tolerance on the contacts' slips; 0: on |y| (a scene's model)
    integer(c_int), intent(in) :: slip_size
    integer(c_int64_t), intent(out) :: handle
    integer(c_int), intent(out) :: status, elem_kind, elem_index
    type(stickslip_model) :: m
    type(model_system) :: sys
    type(prepared_simulation), pointer :: prep
    type(drive_plan) :: plan
    character(len=NAME_LEN), allocatable :: keys(:), ck(:)
    integer :: ek, ei, code

    handle = 0
    elem_kind = 0
    elem_index = 0
    status = SS_BAD_DIM
    keys = split_names(pkeys)
    if (size(keys) /= npv .or. ncp /= nc + 1) return
    call model_from_arrays(m, bodies, springs, dampers, forces, contacts, con_ptr, keys, pvals, signals, sig_start, &
                           tables, drives, slip_size /= 0)
    allocate(prep)
    call m%build_run(sys, prep%sys, status, ek, ei, plan)
    elem_kind = ek
    elem_index = ei
    code = code_of('method', method)
    ck = split_names(ckeys)
    if (status == SS_OK .and. code == 0) status = SS_BAD_METHOD
    if (status == SS_OK .and. n /= m%state_size(sys)) status = SS_BAD_DIM
    if (status == SS_OK) status = new_controls(code, prep%sys, ck, cvals, prep%ctl)
    if (status /= SS_OK) then
        deallocate(prep)
        return
    end if
    prep%method = code
    prep%y0 = y0
    if (ndr > 0) then                   ! the free bodies run; the drives give the others
        prep%y0 = m%free_state(plan, y0)
        allocate(prep%drives)
        prep%drives%method = method
        prep%drives%rtol = rtol(1)
        prep%drives%atol = atol(1)
        prep%drives%h = control_step(ck, cvals)
        prep%drives%plan = plan
        prep%drives%sys = sys
        prep%drives%model = m
    end if
    prep%rtol = rtol
    prep%atol = atol
    prep%t_end = t_end
    handle = transfer(c_loc(prep), handle)
end subroutine prepare_model_run

!> Release a setting of prepare_run or prepare_model_run (handle 0: nothing to do). The handle is invalid after.
subroutine free_prepared(handle)
    use, intrinsic :: iso_c_binding, only: c_int64_t, c_ptr, c_null_ptr, c_f_pointer
    use stickslip_simulate, only: prepared_simulation
    implicit none
    integer(c_int64_t), intent(in) :: handle
    type(prepared_simulation), pointer :: prep
    if (handle == 0) return
    call c_f_pointer(transfer(handle, c_null_ptr), prep)
    deallocate(prep)
end subroutine free_prepared

!> Simulate nset parameter sets in one call (stickslip_batch), OpenMP over the sets.
!! Per set: codes scene/law/method, pvals(:, i) for the names pkeys (NaN: default),
!! nstate(i) and y0(1:nstate(i), i), t_end, rtol, atol, cvals(:, i) for the names ckeys
!! (NaN: not given). n_grid: monitor grid points per set; nkeep = n_grid to return
!! y_grid, 0 not to. istats(:, i) / rstats(:, i): the summary fields named by the
!! registry's 'batch' record; yend(:, i) the state at the last grid time written.
subroutine run_batch(nset, scene, law, method, pkeys, np, pvals, nstate, nmax, y0, t_end, rtol, atol, &
                     ckeys, nc, cvals, n_grid, nkeep, threads, ni, istats, nr, rstats, yend, y_grid, &
                     stop, status)
    use, intrinsic :: iso_c_binding, only: c_int, c_double
    use stickslip_kinds, only: SS_OK
    use stickslip_batch, only: batch_summary, simulate_batch, batch_tables
    use stickslip_registry, only: split_names
    use stickslip_wrap_interrupt, only: arm, disarm
    implicit none
    integer(c_int), intent(in) :: nset, np, nmax, nc, n_grid, nkeep, threads, ni, nr
    integer(c_int), intent(in) :: scene(nset), law(nset), method(nset), nstate(nset)
    !f2py integer intent(hide), depend(scene) :: nset = len(scene)
    character(len=*), intent(in) :: pkeys, ckeys
    real(c_double), intent(in) :: pvals(np, nset)
    !f2py integer intent(hide), depend(pvals) :: np = shape(pvals, 0)
    real(c_double), intent(in) :: y0(nmax, nset)
    !f2py integer intent(hide), depend(y0) :: nmax = shape(y0, 0)
    real(c_double), intent(in) :: t_end(nset), rtol(nset), atol(nset)
    real(c_double), intent(in) :: cvals(nc, nset)
    !f2py integer intent(hide), depend(cvals) :: nc = shape(cvals, 0)
    real(c_double), intent(out) :: istats(ni, nset)
    real(c_double), intent(out) :: rstats(nr, nset)
    real(c_double), intent(out) :: yend(nmax, nset)
    real(c_double), intent(out) :: y_grid(nmax, nkeep, nset)
    integer(c_int), intent(inout), target :: stop(1)
    integer(c_int), intent(out) :: status
    !f2py threadsafe
    type(batch_summary), allocatable :: s(:)
    integer, pointer :: flag
    logical :: armed
    flag => stop(1)
    call arm(stop(1), armed)

    allocate(s(nset))
    istats = 0.0_c_double
    rstats = 0.0_c_double
    y_grid = 0.0_c_double
    yend = 0.0_c_double
    if (nkeep > 0) then
        call simulate_batch(scene, law, method, split_names(pkeys), pvals, nstate, y0, t_end, rtol, atol, &
                            split_names(ckeys), cvals, n_grid, threads, s, status, y_grid, stop_flag=flag)
    else
        call simulate_batch(scene, law, method, split_names(pkeys), pvals, nstate, y0, t_end, rtol, atol, &
                            split_names(ckeys), cvals, n_grid, threads, s, status, stop_flag=flag)
    end if
    call disarm(armed)
    if (status /= SS_OK) return
    call batch_tables(s, istats, rstats, yend, status)
end subroutine run_batch

!> Simulate nset models (stickslip_batch's simulate_model_batch), OpenMP over the sets, each
!! given as prepare_model_run's arrays, those of every set concatenated: set i's columns of bodies,
!! springs, dampers, forces, contacts, its entries of con_ptr (from 1 for its own parameters),
!! of the parameter names pkeys (space-separated) and values pvals, its columns of signals,
!! its entries of sig_start (from 1 for its own operations), its columns of tables and drives
!! start at offsets(k, i) for k = 1 .. 11 in that order and end before offsets(k, i + 1).
!! method(i): method code; nstate, y0, t_end, rtol, atol, ckeys, cvals, n_grid, nkeep, threads
!! and the outputs as run_batch's; events(:, :, i): set i's stick/slip events under event_driven
!! (as prepare_model_run's, room nev each; 0: none kept); elem(:, i): a set's bad element (kind, index from 1; 0: none),
!! when its status (istats) is a bad-input code, and then no set ran.
subroutine run_model_batch(nset, method, bodies, nbt, springs, nst, dampers, ndt, forces, nft, contacts, nct, &
                           con_ptr, ncpt, pkeys, pvals, npv, signals, nop, sig_start, nss, tables, ntab, drives, ndr, &
                           offsets, slip_size, nstate, nmax, y0, t_end, rtol, atol, ckeys, nc, cvals, n_grid, nkeep, &
                           threads, events, nev, ni, istats, nr, rstats, yend, y_grid, elem, stop, status)
    use, intrinsic :: iso_c_binding, only: c_int, c_double
    use stickslip_kinds, only: SS_OK, SS_BAD_DIM
    use stickslip_params, only: NAME_LEN
    use stickslip_batch, only: batch_summary, simulate_model_batch, batch_tables
    use stickslip_registry, only: split_names
    use stickslip_user_model, only: stickslip_model, model_from_arrays
    use stickslip_wrap_interrupt, only: arm, disarm
    implicit none
    integer(c_int), intent(in) :: nset, nbt, nst, ndt, nft, nct, ncpt, npv, nop, nss, ntab, ndr, nmax, nc
    integer(c_int), intent(in) :: n_grid, nkeep, threads, ni, nr, nev
    integer(c_int), intent(in) :: method(nset), nstate(nset)
    !f2py integer intent(hide), depend(method) :: nset = len(method)
    !> each row's model's slip_error_size (1: the error sized on the contacts' slips; 0: on |y|)
    integer(c_int), intent(in) :: slip_size(nset)
    real(c_double), intent(in) :: bodies(3, nbt)
    !f2py integer intent(hide), depend(bodies) :: nbt = shape(bodies, 1)
    real(c_double), intent(in) :: springs(4, nst)
    !f2py integer intent(hide), depend(springs) :: nst = shape(springs, 1)
    real(c_double), intent(in) :: dampers(3, ndt)
    !f2py integer intent(hide), depend(dampers) :: ndt = shape(dampers, 1)
    real(c_double), intent(in) :: forces(2, nft)
    !f2py integer intent(hide), depend(forces) :: nft = shape(forces, 1)
    real(c_double), intent(in) :: contacts(5, nct)
    !f2py integer intent(hide), depend(contacts) :: nct = shape(contacts, 1)
    integer(c_int), intent(in) :: con_ptr(ncpt)
    !f2py integer intent(hide), depend(con_ptr) :: ncpt = len(con_ptr)
    character(len=*), intent(in) :: pkeys, ckeys
    real(c_double), intent(in) :: pvals(npv)
    !f2py integer intent(hide), depend(pvals) :: npv = len(pvals)
    real(c_double), intent(in) :: signals(5, nop)
    !f2py integer intent(hide), depend(signals) :: nop = shape(signals, 1)
    integer(c_int), intent(in) :: sig_start(nss)
    !f2py integer intent(hide), depend(sig_start) :: nss = len(sig_start)
    real(c_double), intent(in) :: tables(2, ntab)
    !f2py integer intent(hide), depend(tables) :: ntab = shape(tables, 1)
    real(c_double), intent(in) :: drives(3, ndr)
    !f2py integer intent(hide), depend(drives) :: ndr = shape(drives, 1)
    integer(c_int), intent(in) :: offsets(11, nset + 1)
    real(c_double), intent(in) :: y0(nmax, nset)
    !f2py integer intent(hide), depend(y0) :: nmax = shape(y0, 0)
    real(c_double), intent(in) :: t_end(nset), rtol(nset), atol(nset)
    real(c_double), intent(in) :: cvals(nc, nset)
    !f2py integer intent(hide), depend(cvals) :: nc = shape(cvals, 0)
    real(c_double), intent(inout) :: events(4, nev, nset)
    !f2py integer intent(hide), depend(events) :: nev = shape(events, 1)
    real(c_double), intent(out) :: istats(ni, nset)
    real(c_double), intent(out) :: rstats(nr, nset)
    real(c_double), intent(out) :: yend(nmax, nset)
    real(c_double), intent(out) :: y_grid(nmax, nkeep, nset)
    integer(c_int), intent(out) :: elem(2, nset)
    integer(c_int), intent(inout), target :: stop(1)
    integer(c_int), intent(out) :: status
    !f2py threadsafe
    type(batch_summary), allocatable :: s(:)
    type(stickslip_model), allocatable :: models(:)
    character(len=NAME_LEN), allocatable :: keys(:)
    integer :: i
    integer, pointer :: flag
    logical :: armed

    istats = 0.0_c_double
    rstats = 0.0_c_double
    y_grid = 0.0_c_double
    yend = 0.0_c_double
    elem = 0
    keys = split_names(pkeys)
    status = SS_BAD_DIM
    if (size(keys) /= npv .or. any(offsets < 1) .or. any(offsets(:, 2:) < offsets(:, :nset))) return
    if (any(offsets(:, nset + 1) /= [nbt, nst, ndt, nft, nct, ncpt, npv, nop, nss, ntab, ndr] + 1)) return
    allocate(models(nset), s(nset))
    do i = 1, nset
        associate (a => offsets(:, i), b => offsets(:, i + 1) - 1)
            call model_from_arrays(models(i), bodies(:, a(1):b(1)), springs(:, a(2):b(2)), dampers(:, a(3):b(3)), &
                                   forces(:, a(4):b(4)), contacts(:, a(5):b(5)), con_ptr(a(6):b(6)), &
                                   keys(a(7):b(7)), pvals(a(7):b(7)), signals(:, a(8):b(8)), sig_start(a(9):b(9)), &
                                   tables(:, a(10):b(10)), drives(:, a(11):b(11)), slip_size(i) /= 0)
        end associate
    end do
    flag => stop(1)
    call arm(stop(1), armed)
    if (nkeep > 0) then
        call simulate_model_batch(models, method, nstate, y0, t_end, rtol, atol, split_names(ckeys), cvals, &
                                  n_grid, threads, events, s, status, y_grid, stop_flag=flag)
    else
        call simulate_model_batch(models, method, nstate, y0, t_end, rtol, atol, split_names(ckeys), cvals, &
                                  n_grid, threads, events, s, status, stop_flag=flag)
    end if
    call disarm(armed)
    if (status /= SS_OK) return
    elem(1, :) = s%elem_kind
    elem(2, :) = s%elem_index
    call batch_tables(s, istats, rstats, yend, status)
end subroutine run_model_batch

!> Names of the integer and real summary fields of run_batch, as 'ints|reals'.
subroutine batch_names(text)
    use stickslip_batch, only: BATCH_INTEGER_NAMES, BATCH_REAL_NAMES
    implicit none
    character(len=1024), intent(out) :: text
    text = BATCH_INTEGER_NAMES // '|' // BATCH_REAL_NAMES
end subroutine batch_names

!> Number of internal states of law `law` with the named parameters (pkeys/pvals as for
!! friction), and their names with units joined by ';' (NUL-padded).
subroutine law_states(law, pkeys, pvals, np, nz, labels, status)
    use, intrinsic :: iso_c_binding, only: c_int, c_double
    use stickslip_kinds, only: SS_OK
    use stickslip_params, only: param_values
    use stickslip_friction, only: friction_law
    use stickslip_registry, only: make_law, split_names
    implicit none
    integer(c_int), intent(in) :: law
    character(len=*), intent(in) :: pkeys
    integer(c_int), intent(in) :: np
    real(c_double), intent(in) :: pvals(np)
    !f2py integer intent(hide), depend(pvals) :: np = len(pvals)
    integer(c_int), intent(out) :: nz
    character(len=4096), intent(out) :: labels
    integer(c_int), intent(out) :: status
    class(friction_law), allocatable :: fl
    type(param_values) :: p
    character(len=:), allocatable :: joined
    integer :: k
    nz = 0
    labels = ''
    status = make_law(law, split_names(pkeys), pvals, fl, p)
    if (status /= SS_OK) return
    nz = fl%n_states()
    joined = ''
    do k = 1, nz
        joined = joined // merge(';', ' ', k > 1) // fl%state_label(k)
    end do
    labels = adjustl(joined)
end subroutine law_states

!> The friction force of law `law` (parameters pkeys/pvals) along the sampled motion (t, x, v)
!! with normal force nf (1 value or n), initial states z0(nz) (nz must be the law's count),
!! backlash [m], asymmetry [-] and rtol (stickslip_prescribed). counters: n_advance,
!! n_unconverged, max_substeps. msub: empty (the step-doubling choice) or the substeps per
!! piece of each sample interval (n - 1 values, a frozen mesh); msub_out: those used.
subroutine prescribed(law, pkeys, pvals, np, t, x, v, n, nf, nnf, z0, nz, backlash, asymmetry, rtol, &
                      msub, nms, force, mu, z, xc, vc, counters, msub_out, status)
    use, intrinsic :: iso_c_binding, only: c_int, c_double
    use stickslip_kinds, only: SS_OK, SS_BAD_DIM
    use stickslip_params, only: param_values
    use stickslip_friction, only: friction_law
    use stickslip_registry, only: make_law, split_names
    use stickslip_prescribed, only: prescribed_motion, prescribed_stats
    implicit none
    integer(c_int), intent(in) :: law
    character(len=*), intent(in) :: pkeys
    integer(c_int), intent(in) :: np, n, nnf, nz
    real(c_double), intent(in) :: pvals(np)
    !f2py integer intent(hide), depend(pvals) :: np = len(pvals)
    real(c_double), intent(in) :: t(n), x(n), v(n)
    !f2py integer intent(hide), depend(t) :: n = len(t)
    real(c_double), intent(in) :: nf(nnf)
    !f2py integer intent(hide), depend(nf) :: nnf = len(nf)
    real(c_double), intent(in) :: z0(nz)
    !f2py integer intent(hide), depend(z0) :: nz = len(z0)
    real(c_double), intent(in) :: backlash, asymmetry, rtol
    integer(c_int), intent(in) :: nms
    integer(c_int), intent(in) :: msub(nms)
    !f2py integer intent(hide), depend(msub) :: nms = len(msub)
    real(c_double), intent(out) :: force(n), mu(n), xc(n), vc(n)
    real(c_double), intent(out) :: z(nz, n)
    real(c_double), intent(out) :: counters(3)
    integer(c_int), intent(out) :: msub_out(n)
    integer(c_int), intent(out) :: status
    !f2py threadsafe
    class(friction_law), allocatable :: fl
    type(param_values) :: p
    type(prescribed_stats) :: st
    force = 0.0_c_double
    mu = 0.0_c_double
    xc = 0.0_c_double
    vc = 0.0_c_double
    z = 0.0_c_double
    counters = 0.0_c_double
    msub_out = 0
    status = make_law(law, split_names(pkeys), pvals, fl, p)
    if (status /= SS_OK) return
    if (fl%n_states() /= nz) then
        status = SS_BAD_DIM
        return
    end if
    if (nms > 0) then
        call prescribed_motion(fl, t, x, v, nf, z0, backlash, asymmetry, rtol, force, mu, z, xc, vc, st, &
                               substeps_in=msub, substeps_out=msub_out)
    else
        call prescribed_motion(fl, t, x, v, nf, z0, backlash, asymmetry, rtol, force, mu, z, xc, vc, st, &
                               substeps_out=msub_out)
    end if
    status = st%status
    counters = [real(st%n_advance, c_double), real(st%n_unconverged, c_double), real(st%max_substeps, c_double)]
end subroutine prescribed

!> A periodic orbit of a user's model given as prepare_model_run's arrays (stickslip_orbit's
!! model_periodic_orbit): from the guess y0 (x, v of every body) and the period (the forcing
!! period, or the guess of the period when autonomous = 1) with the method named `method`
!! and its controls; the solver's options tol, max_iter (0: the monodromy at the guess only),
!! fd_newton, fd_monodromy. Returns the state y_out, the period, the monodromy (want_mono = 1)
!! and its eigenvalues largest modulus first, info = (residual, iterations, runs, trivial
!! index from 1 or 0, stable 1/0), the status and a bad element's kind and index.
subroutine orbit_model(bodies, nb, springs, ns, dampers, nd, forces, nf, contacts, nc, con_ptr, ncp, &
                       pkeys, pvals, npv, signals, nop, sig_start, nss, tables, ntab, drives, ndr, &
                       method, y0, n, period, autonomous, rtol, nrt, atol, nat, ckeys, cvals, ncv, &
                       tol, max_iter, fd_newton, fd_monodromy, want_mono, y_out, period_out, mono, mult_re, &
                       mult_im, info, status, elem_kind, elem_index, slip_size)
    use, intrinsic :: iso_c_binding, only: c_int, c_double
    use stickslip_kinds, only: SS_BAD_DIM
    use stickslip_params, only: NAME_LEN
    use stickslip_registry, only: split_names
    use stickslip_user_model, only: stickslip_model, model_from_arrays
    use stickslip_orbit, only: orbit_options, orbit_result, model_periodic_orbit
    implicit none
    integer(c_int), intent(in) :: nb, ns, nd, nf, nc, ncp, npv, nop, nss, ntab, ndr, n, nrt, nat, ncv
    real(c_double), intent(in) :: bodies(3, nb)
    !f2py integer intent(hide), depend(bodies) :: nb = shape(bodies, 1)
    real(c_double), intent(in) :: springs(4, ns)
    !f2py integer intent(hide), depend(springs) :: ns = shape(springs, 1)
    real(c_double), intent(in) :: dampers(3, nd)
    !f2py integer intent(hide), depend(dampers) :: nd = shape(dampers, 1)
    real(c_double), intent(in) :: forces(2, nf)
    !f2py integer intent(hide), depend(forces) :: nf = shape(forces, 1)
    real(c_double), intent(in) :: contacts(5, nc)
    !f2py integer intent(hide), depend(contacts) :: nc = shape(contacts, 1)
    integer(c_int), intent(in) :: con_ptr(ncp)
    !f2py integer intent(hide), depend(con_ptr) :: ncp = len(con_ptr)
    character(len=*), intent(in) :: pkeys, ckeys, method
    real(c_double), intent(in) :: pvals(npv)
    !f2py integer intent(hide), depend(pvals) :: npv = len(pvals)
    real(c_double), intent(in) :: signals(5, nop)
    !f2py integer intent(hide), depend(signals) :: nop = shape(signals, 1)
    integer(c_int), intent(in) :: sig_start(nss)
    !f2py integer intent(hide), depend(sig_start) :: nss = len(sig_start)
    real(c_double), intent(in) :: tables(2, ntab)
    !f2py integer intent(hide), depend(tables) :: ntab = shape(tables, 1)
    real(c_double), intent(in) :: drives(3, ndr)
    !f2py integer intent(hide), depend(drives) :: ndr = shape(drives, 1)
    real(c_double), intent(in) :: y0(n)
    !f2py integer intent(hide), depend(y0) :: n = len(y0)
    real(c_double), intent(in) :: period
    integer(c_int), intent(in) :: autonomous
    real(c_double), intent(in) :: rtol(nrt)
    !f2py integer intent(hide), depend(rtol) :: nrt = len(rtol)
    real(c_double), intent(in) :: atol(nat)
    !f2py integer intent(hide), depend(atol) :: nat = len(atol)
    real(c_double), intent(in) :: cvals(ncv)
    !f2py integer intent(hide), depend(cvals) :: ncv = len(cvals)
    real(c_double), intent(in) :: tol, fd_newton, fd_monodromy
    integer(c_int), intent(in) :: max_iter, want_mono
    real(c_double), intent(out) :: y_out(n)
    real(c_double), intent(out) :: period_out
    real(c_double), intent(out) :: mono(n, n)
    real(c_double), intent(out) :: mult_re(n), mult_im(n)
    real(c_double), intent(out) :: info(5)
    integer(c_int), intent(out) :: status, elem_kind, elem_index
    !> 1: the adaptive methods' tolerance on the contacts' slips; 0: on |y| (as prepare_model_run's)
    integer(c_int), intent(in) :: slip_size
    !f2py integer optional, intent(in) :: slip_size = 1
    !f2py threadsafe
    type(stickslip_model) :: m
    type(orbit_options) :: opts
    type(orbit_result) :: orb
    integer :: ek, ei
    character(len=NAME_LEN), allocatable :: keys(:)

    y_out = y0
    period_out = period
    mono = 0.0_c_double
    mult_re = 0.0_c_double
    mult_im = 0.0_c_double
    info = 0.0_c_double
    elem_kind = 0
    elem_index = 0
    keys = split_names(pkeys)
    if (size(keys) /= npv .or. ncp /= nc + 1) then
        status = SS_BAD_DIM
        return
    end if
    call model_from_arrays(m, bodies, springs, dampers, forces, contacts, con_ptr, keys, pvals, signals, sig_start, &
                           tables, drives, slip_size /= 0)
    opts%tol = tol
    opts%max_iter = max_iter
    opts%fd_newton = fd_newton
    opts%fd_monodromy = fd_monodromy
    opts%monodromy = want_mono /= 0
    call model_periodic_orbit(m, method, y0, period, autonomous /= 0, rtol, atol, split_names(ckeys), cvals, &
                              opts, orb, ek, ei)
    status = orb%status
    elem_kind = ek
    elem_index = ei
    if (.not. allocated(orb%y0)) return
    if (size(orb%y0) /= n) return
    y_out = orb%y0
    period_out = orb%period
    info = [orb%residual, real(orb%iterations, c_double), real(orb%runs, c_double), real(orb%trivial, c_double), &
            merge(1.0_c_double, 0.0_c_double, orb%stable)]
    if (size(orb%monodromy, 1) == n .and. size(orb%mult_re) == n) then
        mono = orb%monodromy
        mult_re = orb%mult_re
        mult_im = orb%mult_im
    end if
end subroutine orbit_model

!> The sizes of a scene's model as its preset builds it (stickslip_registry's preset_model):
!! sizes = (bodies, springs, dampers, forces, contacts), for preset_arrays.
subroutine preset_sizes(scene, law, pkeys, pvals, np, sizes, status)
    use, intrinsic :: iso_c_binding, only: c_int, c_double
    use stickslip_kinds, only: SS_OK
    use stickslip_params, only: param_values
    use stickslip_model_system, only: model_system
    use stickslip_registry, only: preset_model, split_names
    implicit none
    integer(c_int), intent(in) :: scene, law
    character(len=*), intent(in) :: pkeys
    integer(c_int), intent(in) :: np
    real(c_double), intent(in) :: pvals(np)
    !f2py integer intent(hide), depend(pvals) :: np = len(pvals)
    integer(c_int), intent(out) :: sizes(5)
    integer(c_int), intent(out) :: status
    type(model_system) :: ms
    type(param_values) :: p
    sizes = 0
    status = preset_model(scene, law, split_names(pkeys), pvals, ms, p)
    if (status == SS_OK) sizes = [ms%nb, size(ms%spr_k), size(ms%dmp_c), size(ms%frc_body), size(ms%con_a)]
end subroutine preset_sizes

!> A scene's model as its preset builds it, as the arrays of a user's model (body indices
!! from 1, 0 the ground; its signals are numbers, given by value): mass(nb) [kg],
!! springs(4, ns) = (a, b, k [N/m], rest length [m]), dampers(3, nd) = (a, b, c [N s/m]),
!! forces(2, nf) = (body, force [N]), contacts(4, nc) = (a, b, normal force [N], surface
!! velocity [m/s]); the sizes from preset_sizes. The law is the contacts' own (law, pkeys).
subroutine preset_arrays(scene, law, pkeys, pvals, np, nb, ns, nd, nf, nc, mass, springs, dampers, forces, &
                         contacts, status)
    use, intrinsic :: iso_c_binding, only: c_int, c_double
    use stickslip_kinds, only: SS_OK, SS_BAD_DIM
    use stickslip_params, only: param_values
    use stickslip_model_system, only: model_system
    use stickslip_registry, only: preset_model, split_names
    implicit none
    integer(c_int), intent(in) :: scene, law
    character(len=*), intent(in) :: pkeys
    integer(c_int), intent(in) :: np, nb, ns, nd, nf, nc
    real(c_double), intent(in) :: pvals(np)
    !f2py integer intent(hide), depend(pvals) :: np = len(pvals)
    real(c_double), intent(out) :: mass(nb), springs(4, ns), dampers(3, nd), forces(2, nf), contacts(4, nc)
    integer(c_int), intent(out) :: status
    type(model_system) :: ms
    type(param_values) :: p
    integer :: i
    mass = 0.0_c_double
    springs = 0.0_c_double
    dampers = 0.0_c_double
    forces = 0.0_c_double
    contacts = 0.0_c_double
    status = preset_model(scene, law, split_names(pkeys), pvals, ms, p)
    if (status /= SS_OK) return
    if (nb /= ms%nb .or. ns /= size(ms%spr_k) .or. nd /= size(ms%dmp_c) .or. nf /= size(ms%frc_body) .or. &
        nc /= size(ms%con_a)) then
        status = SS_BAD_DIM
        return
    end if
    mass = ms%mass
    springs = reshape([(real([ms%spr_a(i), ms%spr_b(i)], c_double), ms%spr_k(i), ms%spr_l0(i), i = 1, ns)], [4, ns])
    dampers = reshape([(real([ms%dmp_a(i), ms%dmp_b(i)], c_double), ms%dmp_c(i), i = 1, nd)], [3, nd])
    do i = 1, nf
        forces(:, i) = [real(ms%frc_body(i), c_double), ms%sig%number(ms%frc_sig(i))]
    end do
    do i = 1, nc
        contacts(1:3, i) = [real(ms%con_a(i), c_double), real(ms%con_b(i), c_double), ms%sig%number(ms%con_n(i))]
        if (ms%con_w(i) > 0) contacts(4, i) = ms%sig%number(ms%con_w(i))
    end do
end subroutine preset_arrays
