!> Fortran tests of the presets (stickslip_presets) that Python does not reach: every preset's
!! analytic Jacobian against the forward-difference default, under a static law and the
!! proposed law. Prints one line per check; exits with status 1 if any check fails.
program test_stickslip_presets
    use test_support, only: check, finish
    use stickslip_kinds, only: dp, SS_OK
    use stickslip_params, only: param_values, NAME_LEN
    use stickslip_ode, only: fd_jacobian
    use stickslip_model_system, only: model_system
    use stickslip_registry, only: LAW_TABLE, SCENE_TABLE, new_system
    implicit none

    call test_scene_jacobians()

    call finish('scene')

contains

    !> The presets' models' analytic Jacobians against the forward-difference default.
    subroutine test_scene_jacobians()
        class(model_system), allocatable :: sys
        type(param_values) :: p
        real(dp) :: y(2), f(2), ja(2, 2), jf(2, 2)
        integer(8) :: nfev
        integer :: scene, law, status
        logical :: ok
        do scene = 1, size(SCENE_TABLE)
            do law = 2, 3
                status = new_system(scene, law, [character(len=NAME_LEN) ::], [real(dp) ::], sys, p)
                y = [0.01_dp, merge(0.004_dp, 1.5_dp - 0.004_dp, scene == 1)]
                call sys%rhs(0.0_dp, y, f)
                nfev = 0
                call sys%jacobian(0.0_dp, y, f, ja, nfev)
                ok = status == SS_OK .and. nfev == 0
                call fd_jacobian(sys, 0.0_dp, y, f, jf, nfev)
                ok = ok .and. nfev == 2 .and. all(abs(ja - jf) <= 1.0e-5_dp * max(1.0_dp, abs(jf)))
                call check(ok, 'scene ' // trim(SCENE_TABLE(scene)%name) // ' / ' // trim(LAW_TABLE(law)%name) // &
                           ': analytic Jacobian = finite differences, no evaluation counted')
            end do
        end do
    end subroutine test_scene_jacobians

end program test_stickslip_presets
