!> One entry point that runs a scene with a friction law and an integrator chosen by
!! code, with the physical parameters and the controls given by name: what the Python
!! layer, the C layer and the batch runs call, so that none repeats the set-up.
!!
!! A run is set up in two parts: `prepare_simulation` builds the scene, its law and the
!! method's options from names once (the part of a short run that is not integration), and
!! `run_prepared` integrates a copy of them. A caller that repeats one setting (the Python
!! facade) keeps the prepared setting and runs it as often as it likes, from any number of
!! threads at once: a run never writes into the prepared setting. `simulate` is the two in one.
module stickslip_simulate
    use stickslip_kinds, only: dp, SS_OK, SS_BAD_DIM
    use stickslip_params, only: param_values, NAME_LEN
    use stickslip_ode, only: ode_stats, step_controls
    use stickslip_model_system, only: model_system
    use stickslip_registry, only: new_system, new_controls, integrate
    use stickslip_user_model, only: drive_run
    implicit none
    private

    public :: simulate, prepare_simulation, run_prepared, prepared_sizes

    !> A setting of `simulate` built once: the scene with its law, the method's options and
    !! the run's initial state, tolerances and end time; for a model with drives, its
    !! system is that of the free bodies (y0 theirs) and `drives` the rest. Read-only for
    !! `run_prepared`.
    type, public :: prepared_simulation
        integer :: method = 0                               !! method code (registry)
        class(model_system), allocatable :: sys             !! the scene's model with its law, prepared
        class(step_controls), allocatable :: ctl           !! the method's options, controls set
        real(dp), allocatable :: y0(:)                     !! initial state
        real(dp), allocatable :: rtol(:)                   !! relative tolerance(s)
        real(dp), allocatable :: atol(:)                   !! absolute tolerance(s)
        real(dp) :: t_end = 0.0_dp                         !! final time [s]
        !> A model's drives (`stickslip_user_model`'s drive_run): its output is every body's
        !! state, its driven bodies' from their signals, and each drive's force
        type(drive_run), allocatable :: drives
    end type prepared_simulation

contains

    !> Simulate a scene from y0 = (x0 [m], v0 [m/s], z0...) at t = 0 to t_end.
    !! Parameters not named in pkeys take their defaults; controls not named in ckeys take
    !! the method's defaults. Output and status as for the methods' `<method>_integrate`.
    subroutine simulate(scene, law, method, pkeys, pvals, y0, t_end, rtol, atol, ckeys, cvals, &
                        t_out, y_out, stats, p_out, sys_out, stop_flag, events)
        integer, intent(in) :: scene                !! scene code (registry)
        integer, intent(in) :: law                  !! law code (registry)
        integer, intent(in) :: method               !! method code (registry)
        character(len=*), intent(in) :: pkeys(:)    !! names of the given physical parameters
        real(dp), intent(in) :: pvals(:)            !! their values [SI units]
        real(dp), intent(in) :: y0(:)               !! initial state, size 2 + the law's states
        real(dp), intent(in) :: t_end               !! final time [s]
        real(dp), intent(in) :: rtol(:)             !! relative tolerance(s), size 1 or size(y0)
        real(dp), intent(in) :: atol(:)             !! absolute tolerance(s), size 1 or size(y0)
        character(len=*), intent(in) :: ckeys(:)    !! names of the given controls
        real(dp), intent(in) :: cvals(:)            !! their values (counts and flags as reals)
        real(dp), intent(inout) :: t_out(:)         !! requested output times, or step times [s]
        real(dp), intent(inout) :: y_out(:, :)      !! (size(y0), size(t_out)) states
        type(ode_stats), intent(out) :: stats       !! counters and status
        type(param_values), intent(out), optional :: p_out  !! every parameter as resolved
        class(model_system), allocatable, intent(out), optional :: sys_out  !! the scene's model run
        !> A flag another thread may set nonzero to stop the run (SS_INTERRUPTED).
        integer, pointer, intent(in), optional :: stop_flag
        !> (4, room): the stick/slip events of event_driven, (t [s], kind, position [m], contact)
        real(dp), intent(inout), optional :: events(:, :)
        type(prepared_simulation) :: prep

        stats%status = prepare_simulation(scene, law, pkeys, pvals, method, ckeys, cvals, y0, t_end, rtol, atol, &
                                          prep, p_out)
        if (stats%status /= SS_OK) return
        ! the prepared setting is used once: its scene is run, not a copy
        call integrate(method, prep%sys, 0.0_dp, y0, t_end, rtol, atol, [character(len=NAME_LEN) ::], [real(dp) ::], &
                       t_out, y_out, stats, stop_flag, events, controls=prep%ctl)
        if (present(sys_out)) call move_alloc(prep%sys, sys_out)
    end subroutine simulate

    !> Build a setting of `simulate` (its arguments, grouped: the scene with its law and their
    !! parameters, the method with its controls, the run) for `run_prepared`: the scene with
    !! its law from the named parameters, the method's options from the named controls. SS_OK
    !! or the code of the first bad input, in the order `simulate` names them (parameters, the
    !! state's size, the method and its controls).
    function prepare_simulation(scene, law, pkeys, pvals, method, ckeys, cvals, y0, t_end, rtol, atol, &
                                prep, p_out) result(status)
        integer, intent(in) :: scene                !! scene code (registry)
        integer, intent(in) :: law                  !! law code (registry)
        character(len=*), intent(in) :: pkeys(:)    !! names of the given physical parameters
        real(dp), intent(in) :: pvals(:)            !! their values [SI units]
        integer, intent(in) :: method               !! method code (registry)
        character(len=*), intent(in) :: ckeys(:)    !! names of the given controls
        real(dp), intent(in) :: cvals(:)            !! their values (counts and flags as reals)
        real(dp), intent(in) :: y0(:)               !! initial state, size 2 + the law's states
        real(dp), intent(in) :: t_end               !! final time [s]
        real(dp), intent(in) :: rtol(:)             !! relative tolerance(s), size 1 or size(y0)
        real(dp), intent(in) :: atol(:)             !! absolute tolerance(s), size 1 or size(y0)
        type(prepared_simulation), intent(out) :: prep       !! the setting, ready to run
        type(param_values), intent(out), optional :: p_out  !! every parameter as resolved
        integer :: status
        type(param_values) :: p

        status = new_system(scene, law, pkeys, pvals, prep%sys, p)
        if (present(p_out)) then          ! moved, not copied: p is not read again
            call move_alloc(p%names, p_out%names)
            call move_alloc(p%values, p_out%values)
        end if
        if (status /= SS_OK) return
        if (size(y0) /= prep%sys%n_states()) then
            status = SS_BAD_DIM
            return
        end if
        status = new_controls(method, prep%sys, ckeys, cvals, prep%ctl)
        if (status /= SS_OK) return
        prep%method = method
        prep%y0 = y0
        prep%rtol = rtol
        prep%atol = atol
        prep%t_end = t_end
    end function prepare_simulation

    !> The sizes of a run of a prepared setting: n, its output state's (y0's, or every body's
    !! state for a model with drives), and nd, its drives' (0 without).
    subroutine prepared_sizes(prep, n, nd)
        type(prepared_simulation), intent(in) :: prep  !! the setting
        integer, intent(out) :: n                   !! rows of y_out
        integer, intent(out) :: nd                  !! rows of drive_force
        n = 0
        nd = 0
        if (allocated(prep%y0)) n = size(prep%y0)
        if (.not. allocated(prep%drives)) return
        n = prep%drives%model%state_size(prep%drives%sys)
        nd = size(prep%drives%model%drv_body)
    end subroutine prepared_sizes

    !> Run a setting built by `prepare_simulation` (or a model's, with its drives) on a copy
    !! of its system and options, so that runs of one setting on several threads at once share
    !! nothing they write. Output and status as for `simulate`; SS_BAD_DIM for a setting that
    !! was not prepared. A model with drives runs its free bodies, then gives every body's
    !! state (`prepared_sizes`) and, when asked, each drive's force.
    subroutine run_prepared(prep, t_out, y_out, stats, stop_flag, events, drive_force)
        type(prepared_simulation), intent(in) :: prep  !! the setting (prepare_simulation)
        real(dp), intent(inout) :: t_out(:)         !! requested output times, or step times [s]
        real(dp), intent(inout) :: y_out(:, :)      !! (prepared_sizes' n, size(t_out)) states
        type(ode_stats), intent(out) :: stats       !! counters and status
        !> A flag another thread may set nonzero to stop the run (SS_INTERRUPTED).
        integer, pointer, intent(in), optional :: stop_flag
        !> (4, room): the stick/slip events of event_driven, (t [s], kind, position [m], contact)
        real(dp), intent(inout), optional :: events(:, :)
        !> (prepared_sizes' nd, size(t_out)): each drive's force on its body [N]
        real(dp), intent(out), optional :: drive_force(:, :)
        class(model_system), allocatable :: sys
        type(model_system) :: built               ! this run's copy of the drives' system (its friction writes)
        real(dp), allocatable :: y_free(:, :)

        if (.not. (allocated(prep%sys) .and. allocated(prep%ctl))) then
            stats%status = SS_BAD_DIM
            return
        end if
        allocate(sys, source=prep%sys)       ! integrate copies the options
        if (.not. allocated(prep%drives)) then
            call integrate(prep%method, sys, 0.0_dp, prep%y0, prep%t_end, prep%rtol, prep%atol, &
                           [character(len=NAME_LEN) ::], [real(dp) ::], t_out, y_out, stats, stop_flag, events, &
                           controls=prep%ctl)
            return
        end if
        allocate(y_free(size(prep%y0), size(t_out)))
        y_free = 0.0_dp
        call integrate(prep%method, sys, 0.0_dp, prep%y0, prep%t_end, prep%rtol, prep%atol, &
                       [character(len=NAME_LEN) ::], [real(dp) ::], t_out, y_free, stats, stop_flag, events, &
                       controls=prep%ctl)
        built = prep%drives%sys
        associate (d => prep%drives)
            call d%model%finish_drives(built, d%plan, d%method, d%rtol, d%atol, d%h, t_out, y_free, y_out, &
                                       drive_force)
        end associate
    end subroutine run_prepared

end module stickslip_simulate
