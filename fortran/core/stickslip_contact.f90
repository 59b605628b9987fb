!> Set-valued (exact-stick) friction: the interface of a mechanical system with frictional
!! contacts, as the nonsmooth methods (`stickslip_moreau`, `stickslip_event_driven`) see it,
!! and the set-valued laws with their one-contact solution.
!!
!! The system. Generalized coordinates q and velocities u (n_dof each; units per
!! coordinate, [m] and [m/s] for the built-in scenes), a mass matrix M (n_dof x n_dof,
!! symmetric positive definite, [kg]), non-friction generalized forces f(t, q, u) [N], and
!! n_c frictional contacts. Contact i has
!!   - a normal force N_i(t, q) >= 0 [N];
!!   - a relative sliding velocity w_i = sum_j H(i, j) u_j + b_i(t) [m/s], a linear map of u
!!     (H constant, stored by rows in compressed sparse form: a chain of blocks has one entry
!!     per row) plus an offset (a belt: w = v - v_b, the body's velocity relative to the belt);
!!   - a set-valued law (`contact_law`): the friction force r_i [N] opposes sliding,
!!     r_i = -N_i mu(|w_i|) sign(w_i) when w_i /= 0, and any r_i with |r_i| <= mu_s N_i when
!!     w_i = 0 (stick). The generalized friction force is H^T r.
!! The equations of motion are M u' = f(t, q, u) + H^T r, q' = u.
!!
!! The methods need the system to solve with its iteration matrix
!! W = M + a C + b K (K = -df/dq [N/m], C = -df/du [N s/m], a [s], b [s^2]):
!! `solve_w` does it in place, so that a banded or block-diagonal system keeps its
!! structure (the mass is never formed as a dense matrix here). With a = b = 0 it applies
!! M^-1. `w_constant` tells that W depends on a and b only (a linear, time-invariant
!! system): a method may then factor the contact problem once per step size.
!!
!! The set-valued laws (`contact_law`, defined with the laws' interface in `stickslip_friction`
!! and used from here): Coulomb (stick up to mu_s N, slip at mu_k N at any speed) and the
!! Stribeck curve without regularisation at rest; each library law says its own
!! (`friction_law%set_valued`), so this module names no law.
module stickslip_contact
    use stickslip_kinds, only: dp
    use stickslip_friction, only: friction_law, contact_law, CONTACT_COULOMB, CONTACT_STRIBECK
    implicit none
    private

    public :: contact_law, contact_system, contact_law_of, local_solve

    public :: CONTACT_COULOMB, CONTACT_STRIBECK   !! (from stickslip_friction) the set-valued laws' kinds
    !> Relative tolerance of the static limit: a friction force (or impulse) up to
    !! mu_s N (1 + STICK_RTOL) sticks, so that |F| = mu_s N is stuck in every method [-].
    real(dp), parameter, public :: STICK_RTOL = 1.0e-12_dp

    !> A mechanical system with frictional contacts (see the module notes for the model).
    type, abstract :: contact_system
        integer :: n_dof = 0                       !! generalized coordinates (and velocities)
        integer :: n_c = 0                         !! frictional contacts
        integer, allocatable :: h_ptr(:)           !! (n_c + 1) row starts of H in h_col/h_val
        integer, allocatable :: h_col(:)           !! column (coordinate) of each entry of H
        real(dp), allocatable :: h_val(:)          !! value of each entry of H [-]
        type(contact_law), allocatable :: laws(:)  !! (n_c) the law of each contact
        logical :: w_constant = .false.            !! W = M + a C + b K depends on a, b only
    contains
        !> f(t, q, u): the non-friction generalized forces [N].
        procedure(force_iface), deferred :: force
        !> x := (M + a C + b K)^-1 x, at (t, q, u).
        procedure(solve_w_iface), deferred :: solve_w
        !> The normal forces N_i(t, q) >= 0 [N] of every contact.
        procedure(normal_iface), deferred :: normal_forces
        !> The offsets b_i(t) of the relative velocities [m/s] (default 0).
        procedure :: slip_offset => zero_offset
        !> Their rates db_i/dt [m/s^2] (default 0; the event-driven method reads them).
        procedure :: offset_rate => zero_offset
        !> w = H u + b(t) [m/s].
        procedure :: relative_velocities
        !> w = H x (no offset).
        procedure :: apply_h
        !> g := g + H^T r [N] (or impulses [N s]).
        procedure :: add_ht
        !> The slip displacement of contact i, H_i q [m] (the body's coordinate for a contact
        !! on one body with H_i = 1; a relative displacement for a contact between bodies).
        procedure :: contact_displacement
        !> W = M + a C + b K as three diagonals when it is tridiagonal (ok); the default says
        !! it is not (ok = .false.). Moreau's solver then works on W itself, O(n) a sweep.
        procedure :: w_tridiagonal => not_tridiagonal
        !> The first time after t where the system's forces, normal forces or offsets have a
        !! corner (a step of a time signal) [s]; huge(1.0_dp) by default (none). The event-driven
        !! method stops there and decides the modes afresh.
        procedure :: next_time_event => no_time_event
        !> The shortest time over which the forces, normal forces or offsets vary smoothly in
        !! time between corners (a sine's period) [s]; huge(1.0_dp) by default (they do not).
        !! The event-driven method keeps its steps to a fraction of it, so that a holding force
        !! that follows the signal is sampled densely enough to see where it exceeds the limit.
        procedure :: time_scale => no_time_scale
        !> How a fixed-step method solves its friction problem with W = M + a C + b K: on W
        !! itself where W is tridiagonal and each contact acts on one coordinate of its own,
        !! otherwise on the Delassus matrix (allocated here).
        procedure :: step_layout
        !> The Delassus matrix D = H W^-1 H^T of W = M + a C + b K at (t, q, u), column by
        !! column (n_c solves with W).
        procedure :: delassus
    end type contact_system

    abstract interface
        subroutine force_iface(self, t, q, u, f)
            import :: contact_system, dp
            class(contact_system), intent(in) :: self
            real(dp), intent(in)  :: t          !! time [s]
            real(dp), intent(in)  :: q(:)       !! coordinates [m]
            real(dp), intent(in)  :: u(:)       !! velocities [m/s]
            real(dp), intent(out) :: f(:)       !! non-friction forces [N]
        end subroutine force_iface

        subroutine solve_w_iface(self, t, q, u, a, b, x)
            import :: contact_system, dp
            class(contact_system), intent(in) :: self
            real(dp), intent(in)    :: t        !! time [s]
            real(dp), intent(in)    :: q(:)     !! coordinates [m]
            real(dp), intent(in)    :: u(:)     !! velocities [m/s]
            real(dp), intent(in)    :: a        !! weight of C = -df/du [s]
            real(dp), intent(in)    :: b        !! weight of K = -df/dq [s^2]
            real(dp), intent(inout) :: x(:)     !! right-hand side [N s], then the solution [m/s]
        end subroutine solve_w_iface

        subroutine normal_iface(self, t, q, n)
            import :: contact_system, dp
            class(contact_system), intent(in) :: self
            real(dp), intent(in)  :: t          !! time [s]
            real(dp), intent(in)  :: q(:)       !! coordinates [m]
            real(dp), intent(out) :: n(:)       !! normal force of each contact, >= 0 [N]
        end subroutine normal_iface
    end interface

contains

    subroutine zero_offset(self, t, b)
        class(contact_system), intent(in) :: self
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(out) :: b(:)       !! offset of each relative velocity [m/s] (or its rate [m/s^2])
        b = 0.0_dp
    end subroutine zero_offset

    subroutine relative_velocities(self, t, u, w)
        class(contact_system), intent(in) :: self
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(in)  :: u(:)       !! velocities [m/s]
        real(dp), intent(out) :: w(:)       !! relative sliding velocity of each contact [m/s]
        real(dp) :: s
        integer :: i, k
        call self%slip_offset(t, w)         ! the offsets first, then H u added to each
        do i = 1, self%n_c
            s = 0.0_dp
            do k = self%h_ptr(i), self%h_ptr(i + 1) - 1
                s = s + self%h_val(k) * u(self%h_col(k))
            end do
            w(i) = s + w(i)
        end do
    end subroutine relative_velocities

    pure subroutine apply_h(self, x, w)
        class(contact_system), intent(in) :: self
        real(dp), intent(in)  :: x(:)       !! a vector of generalized velocities [m/s]
        real(dp), intent(out) :: w(:)       !! H x [m/s]
        integer :: i, k
        do i = 1, self%n_c
            w(i) = 0.0_dp
            do k = self%h_ptr(i), self%h_ptr(i + 1) - 1
                w(i) = w(i) + self%h_val(k) * x(self%h_col(k))
            end do
        end do
    end subroutine apply_h

    pure subroutine add_ht(self, r, g)
        class(contact_system), intent(in) :: self
        real(dp), intent(in)    :: r(:)     !! contact forces [N] (or impulses [N s])
        real(dp), intent(inout) :: g(:)     !! generalized forces, H^T r added [N] (or [N s])
        integer :: i, k
        do i = 1, self%n_c
            do k = self%h_ptr(i), self%h_ptr(i + 1) - 1
                g(self%h_col(k)) = g(self%h_col(k)) + self%h_val(k) * r(i)
            end do
        end do
    end subroutine add_ht

    subroutine not_tridiagonal(self, a, b, l, d, r, ok)
        class(contact_system), intent(in) :: self
        real(dp), intent(in)  :: a          !! weight of C [s]
        real(dp), intent(in)  :: b          !! weight of K [s^2]
        real(dp), intent(out) :: l(:)       !! W(i, i - 1), not set here
        real(dp), intent(out) :: d(:)       !! W(i, i), not set here
        real(dp), intent(out) :: r(:)       !! W(i, i + 1), not set here
        logical, intent(out)  :: ok         !! .false.: W is not known to be tridiagonal
        ok = .false.
    end subroutine not_tridiagonal

    pure real(dp) function no_time_event(self, t) result(tb)
        class(contact_system), intent(in) :: self
        real(dp), intent(in) :: t           !! time [s]
        tb = huge(1.0_dp)
    end function no_time_event

    pure real(dp) function no_time_scale(self) result(ts)
        class(contact_system), intent(in) :: self
        ts = huge(1.0_dp)
    end function no_time_scale

    subroutine delassus(self, t, q, u, a, b, d)
        class(contact_system), intent(in) :: self
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(in)  :: q(:)       !! coordinates [m]
        real(dp), intent(in)  :: u(:)       !! velocities [m/s]
        real(dp), intent(in)  :: a          !! weight of C [s]
        real(dp), intent(in)  :: b          !! weight of K [s^2]
        real(dp), intent(out) :: d(:, :)    !! (n_c, n_c) H W^-1 H^T [1/kg]
        real(dp) :: g(self%n_dof), e(self%n_c)
        integer :: c
        do c = 1, self%n_c
            e = 0.0_dp
            e(c) = 1.0_dp
            g = 0.0_dp
            call self%add_ht(e, g)
            call self%solve_w(t, q, u, a, b, g)
            call self%apply_h(g, d(:, c))
        end do
    end subroutine delassus

    !> The layout of a fixed-step method's friction problem with W = M + a C + b K (`a`, `b`
    !! the step's weights): tri when W is tridiagonal (diagonals wl, wd, wr) and each contact
    !! has a single entry in its row of H, on a coordinate no other contact shares; the problem
    !! is then solved on W itself, coord_contact giving the contact on each coordinate (0: none),
    !! and dmat is empty. Otherwise dmat is allocated (n_c, n_c) for the Delassus matrix.
    subroutine step_layout(self, a, b, wl, wd, wr, coord_contact, tri, dmat)
        class(contact_system), intent(in) :: self
        real(dp), intent(in)  :: a                !! weight of C [s]
        real(dp), intent(in)  :: b                !! weight of K [s^2]
        real(dp), intent(out) :: wl(:)            !! (n_dof) W(i, i - 1)
        real(dp), intent(out) :: wd(:)            !! (n_dof) W(i, i)
        real(dp), intent(out) :: wr(:)            !! (n_dof) W(i, i + 1)
        integer, intent(out)  :: coord_contact(:) !! (n_dof) the contact on each coordinate (0: none)
        logical, intent(out)  :: tri              !! solve on W itself
        real(dp), allocatable, intent(out) :: dmat(:, :)  !! (n_c, n_c) room for D, or (0, 0)
        integer :: c, k
        coord_contact = 0
        call self%w_tridiagonal(a, b, wl, wd, wr, tri)
        do c = 1, self%n_c
            if (.not. tri) exit
            k = self%h_ptr(c)
            tri = self%h_ptr(c + 1) - k == 1
            if (tri) tri = coord_contact(self%h_col(k)) == 0
            if (tri) coord_contact(self%h_col(k)) = c
        end do
        if (tri) then
            allocate(dmat(0, 0))
        else
            allocate(dmat(self%n_c, self%n_c))
        end if
    end subroutine step_layout

    !> The displacement of contact i, H_i q [m]; a row of one entry (one body on the ground)
    !! reports that body's position whichever side of the contact it is on (the presets put
    !! the block on side b): |H_i| q.
    pure real(dp) function contact_displacement(self, i, q) result(x)
        class(contact_system), intent(in) :: self
        integer, intent(in) :: i            !! contact index, 1 .. n_c
        real(dp), intent(in) :: q(:)        !! coordinates [m]
        integer :: k
        x = 0.0_dp
        do k = self%h_ptr(i), self%h_ptr(i + 1) - 1
            x = x + self%h_val(k) * q(self%h_col(k))
        end do
        if (self%h_ptr(i + 1) - self%h_ptr(i) == 1) x = sign(1.0_dp, self%h_val(self%h_ptr(i))) * x
    end function contact_displacement

    !> The set-valued law of a library law (`friction_law%set_valued`): Coulomb and Stribeck
    !! have one (their slip curve without the regularisation at rest), Karnopp's is Coulomb's (its
    !! stick band dv is the static set's stand-in); any other law gives SS_NOT_SETVALUED.
    subroutine contact_law_of(law, cl, status)
        class(friction_law), intent(in) :: law  !! a validated friction law
        type(contact_law), intent(out) :: cl    !! its set-valued counterpart
        integer, intent(out) :: status          !! SS_OK or SS_NOT_SETVALUED
        call law%set_valued(cl, status)
    end subroutine contact_law_of

    !> The one-contact problem of an implicit step: w = wf + d p with the impulse
    !! p in -hn F(w), F(w) = mu(|w|) sign(w) for w /= 0 and [-mu_s, mu_s] at w = 0.
    !! Stick (w = 0 exactly, p = -wf/d) when |wf| <= d hn mu_s (1 + STICK_RTOL); otherwise slip in the
    !! direction of wf with s = |w| > 0 solving s + d hn mu(s) = |wf|: in closed form for
    !! Coulomb, by a bracketed Newton iteration to rounding for Stribeck (a root in
    !! (0, |wf|) always exists; when d hn mu'(s) < -1 somewhere there may be several, and the
    !! one found is the one the bracket leads to).
    pure subroutine local_solve(cl, wf, d, hn, w, p)
        type(contact_law), intent(in) :: cl   !! the contact's law
        real(dp), intent(in)  :: wf           !! relative velocity without this contact's impulse [m/s]
        real(dp), intent(in)  :: d            !! w per unit impulse, > 0 [1/kg]
        real(dp), intent(in)  :: hn           !! step times normal force, >= 0 [N s]
        real(dp), intent(out) :: w            !! relative velocity after the impulse [m/s]
        real(dp), intent(out) :: p            !! friction impulse [N s]
        real(dp) :: c, s, s_new, lo, hi, phi, dphi, sig
        integer :: it
        c = d * hn
        if (abs(wf) <= c * cl%mu_s * (1.0_dp + STICK_RTOL)) then
            p = -wf / d
            w = 0.0_dp
            return
        end if
        sig = sign(1.0_dp, wf)
        if (cl%kind == CONTACT_COULOMB) then
            s = abs(wf) - c * cl%mu_k
        else
            ! phi(s) = s + c mu(s) - |wf|: phi(0+) = c mu_s - |wf| < 0, phi(|wf|) > 0.
            lo = 0.0_dp
            hi = abs(wf)
            s = max(abs(wf) - c * cl%mu_k, 0.5_dp * hi)
            do it = 1, 200
                phi = s + c * cl%slip_mu(s) - abs(wf)
                if (phi == 0.0_dp) exit
                if (phi > 0.0_dp) then
                    hi = s
                else
                    lo = s
                end if
                dphi = 1.0_dp + c * cl%slip_dmu(s)
                s_new = 0.5_dp * (lo + hi)
                if (dphi > 0.0_dp) s_new = s - phi / dphi
                if (.not. (s_new > lo .and. s_new < hi)) s_new = 0.5_dp * (lo + hi)
                if (abs(s_new - s) <= 2.0_dp * epsilon(1.0_dp) * s .or. hi - lo <= 2.0_dp * epsilon(1.0_dp) * hi) &
                    exit
                s = s_new
            end do
        end if
        w = sig * s
        p = -sig * hn * cl%slip_mu(s)
    end subroutine local_solve

end module stickslip_contact
