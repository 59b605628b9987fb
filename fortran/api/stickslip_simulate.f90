!> One entry point that runs a scene with a friction law and an integrator chosen by
!! code, with the physical parameters and the controls given by name: what the Python
!! layer, the C layer and the batch runs call, so that none repeats the set-up.
module stickslip_simulate
    use stickslip_kinds, only: dp, SS_OK, SS_BAD_DIM
    use stickslip_params, only: param_values
    use stickslip_ode, only: ode_stats
    use stickslip_scenes, only: friction_scene
    use stickslip_registry, only: new_system, integrate
    implicit none
    private

    public :: simulate

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
        class(friction_scene), allocatable, intent(out), optional :: sys_out  !! the scene run
        !> A flag another thread may set nonzero to stop the run (SS_INTERRUPTED).
        integer, pointer, intent(in), optional :: stop_flag
        !> (4, room): the stick/slip events of event_driven, (t [s], kind, position [m], contact)
        real(dp), intent(inout), optional :: events(:, :)
        class(friction_scene), allocatable :: sys
        type(param_values) :: p

        stats%status = new_system(scene, law, pkeys, pvals, sys, p)
        if (present(p_out)) then          ! moved, not copied: p is not read again
            call move_alloc(p%names, p_out%names)
            call move_alloc(p%values, p_out%values)
        end if
        if (stats%status /= SS_OK) return
        if (size(y0) /= sys%n_states()) then
            stats%status = SS_BAD_DIM
            return
        end if
        call integrate(method, sys, 0.0_dp, y0, t_end, rtol, atol, ckeys, cvals, t_out, y_out, stats, stop_flag, &
                       events)
        if (present(sys_out)) call move_alloc(sys, sys_out)
    end subroutine simulate

end module stickslip_simulate
