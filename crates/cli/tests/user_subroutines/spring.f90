! SFOSUB: a spring-damper between markers PAR(4) and PAR(5),
! F = -PAR(1)*(DM - PAR(3)) - PAR(2)*VR (repulsive positive), reading DM and VR with SYSFNC.
subroutine sfosub(id, time, par, npar, dflag, iflag, result)
  implicit none
  integer, intent(in) :: id, npar
  double precision, intent(in) :: time, par(*)
  logical, intent(in) :: dflag, iflag
  double precision, intent(out) :: result
  integer :: ipar(2)
  double precision :: dm, vr
  logical :: errflg
  ipar(1) = nint(par(4))
  ipar(2) = nint(par(5))
  call sysfnc('DM', ipar, 2, dm, errflg)
  call errmes(errflg, 'DM cannot be read', id, 'STOP')
  call sysfnc('VR', ipar, 2, vr, errflg)
  call errmes(errflg, 'VR cannot be read', id, 'STOP')
  result = -par(1)*(dm - par(3)) - par(2)*vr
end subroutine sfosub

! VARSUB: a PD control law on the height of marker PAR(3) above PAR(4) (ground axes):
! u = -PAR(1)*(DZ - PAR(5)) - PAR(2)*VZ.
subroutine varsub(id, time, par, npar, dflag, iflag, value)
  implicit none
  integer, intent(in) :: id, npar
  double precision, intent(in) :: time, par(*)
  logical, intent(in) :: dflag, iflag
  double precision, intent(out) :: value
  integer :: ipar(4)
  double precision :: dz, vz
  logical :: errflg
  ipar = 0
  ipar(1) = nint(par(3))
  ipar(2) = nint(par(4))
  call sysfnc('DZ', ipar, 3, dz, errflg)
  call sysfnc('VZ', ipar, 4, vz, errflg)
  value = -par(1)*(dz - par(5)) - par(2)*vz
end subroutine varsub

! A subroutine that gives up: ERRMES with STOP once TIME passes PAR(1).
subroutine brittle(id, time, par, npar, dflag, iflag, result)
  implicit none
  integer, intent(in) :: id, npar
  double precision, intent(in) :: time, par(*)
  logical, intent(in) :: dflag, iflag
  double precision, intent(out) :: result
  double precision :: t
  call timget(t)
  result = 0d0
  call errmes(t > par(1), 'the spring broke', id, 'STOP')
end subroutine brittle

! DIFSUB: a first-order lag of the height of marker PAR(2) above PAR(3):
! dy/dt = (DZ - y)/PAR(1), y = DIF(ID).
subroutine difsub(id, time, par, npar, dflag, iflag, value)
  implicit none
  integer, intent(in) :: id, npar
  double precision, intent(in) :: time, par(*)
  logical, intent(in) :: dflag, iflag
  double precision, intent(out) :: value
  integer :: ipar(2), iself(1)
  double precision :: u, y
  logical :: errflg
  ipar(1) = nint(par(2))
  ipar(2) = nint(par(3))
  iself(1) = id
  call sysfnc('DZ', ipar, 2, u, errflg)
  call sysfnc('DIF', iself, 1, y, errflg)
  value = (u - y)/par(1)
end subroutine difsub

! MOTSUB: a sinusoidal drive PAR(3) + PAR(1)*SIN(PAR(2)*TIME) and its two time derivatives
! (IORD = 0, 1, 2).
subroutine motsub(id, time, par, npar, iord, iflag, value)
  implicit none
  integer, intent(in) :: id, npar, iord
  double precision, intent(in) :: time, par(*)
  logical, intent(in) :: iflag
  double precision, intent(out) :: value
  select case (iord)
  case (0)
    value = par(3) + par(1)*sin(par(2)*time)
  case (1)
    value = par(1)*par(2)*cos(par(2)*time)
  case default
    value = -par(1)*par(2)**2*sin(par(2)*time)
  end select
end subroutine motsub

! REQSUB: eight outputs of the block (marker PAR(1) above PAR(2)): TIME, DZ, VZ, ACCZ, DM, VR,
! PAR(3)*DZ and the SFORCE/PAR(4)'s z force on its I marker.
subroutine reqsub(id, time, par, npar, iflag, result)
  implicit none
  integer, intent(in) :: id, npar
  double precision, intent(in) :: time, par(*)
  logical, intent(in) :: iflag
  double precision, intent(out) :: result(8)
  integer :: ipar(4)
  logical :: errflg
  ipar = 0
  ipar(1) = nint(par(1))
  ipar(2) = nint(par(2))
  result(1) = time
  call sysfnc('DZ', ipar, 2, result(2), errflg)
  call sysfnc('VZ', ipar, 4, result(3), errflg)
  call sysfnc('ACCZ', ipar, 4, result(4), errflg)
  call sysfnc('DM', ipar, 2, result(5), errflg)
  call sysfnc('VR', ipar, 2, result(6), errflg)
  result(7) = par(3)*result(2)
  ipar(1) = nint(par(4))
  ipar(2) = 0
  ipar(3) = 4
  ipar(4) = 0
  call sysfnc('SFORCE', ipar, 4, result(8), errflg)
  call errmes(errflg, 'SFORCE cannot be read', id, 'STOP')
end subroutine reqsub

! GFOSUB: a six-component bushing of marker PAR(1) on PAR(2) (RM's axes = PAR(2)'s):
! F_k = PAR(2+k) - PAR(8+k)*(D_k - L_k) - PAR(14+k)*V_k, k = 1…6, D = DX, DY, DZ, AX, AY, AZ,
! V = VX, VY, VZ, WX, WY, WZ, L = 0, 0, PAR(21), 0, 0, 0.
subroutine gfosub(id, time, par, npar, dflag, iflag, result)
  implicit none
  integer, intent(in) :: id, npar
  double precision, intent(in) :: time, par(*)
  logical, intent(in) :: dflag, iflag
  double precision, intent(out) :: result(6)
  character(len=2), parameter :: dname(6) = ['DX', 'DY', 'DZ', 'AX', 'AY', 'AZ']
  character(len=2), parameter :: vname(6) = ['VX', 'VY', 'VZ', 'WX', 'WY', 'WZ']
  integer :: ipar(4), k, nd, nv
  double precision :: d, v, rest
  logical :: errflg
  ipar(1) = nint(par(1))
  ipar(2) = nint(par(2))
  ipar(3) = ipar(2)
  ipar(4) = ipar(2)
  do k = 1, 6
    nd = 3
    nv = 4
    if (k > 3) then
      nd = 2
      nv = 3
    end if
    rest = 0d0
    if (k == 3) rest = par(21)
    call sysfnc(dname(k), ipar, nd, d, errflg)
    call errmes(errflg, 'bushing deflection cannot be read', id, 'STOP')
    call sysfnc(vname(k), ipar, nv, v, errflg)
    call errmes(errflg, 'bushing velocity cannot be read', id, 'STOP')
    result(k) = par(2 + k) - par(8 + k)*(d - rest) - par(14 + k)*v
  end do
end subroutine gfosub

! SENSUB: the height of marker PAR(1) above PAR(2) less PAR(3).
subroutine sensub(id, time, par, npar, iflag, value)
  implicit none
  integer, intent(in) :: id, npar
  double precision, intent(in) :: time, par(*)
  logical, intent(in) :: iflag
  double precision, intent(out) :: value
  integer :: ipar(2)
  logical :: errflg
  ipar(1) = nint(par(1))
  ipar(2) = nint(par(2))
  call sysfnc('DZ', ipar, 2, value, errflg)
  value = value - par(3)
end subroutine sensub

! An SFOSUB built from the function utility routines: IMPACT(DM, VR, PAR(1…5)) + STEP(TIME,
! 0, 0, 1, 2) + POLY(DM, 1, PAR(6…8)) + BISTOP(DM, VR, 0.5, 1.5, 1e4, 1.5, 10, 0.01), the
! block's markers PAR(9), PAR(10).
subroutine utilforce(id, time, par, npar, dflag, iflag, result)
  implicit none
  integer, intent(in) :: id, npar
  double precision, intent(in) :: time, par(*)
  logical, intent(in) :: dflag, iflag
  double precision, intent(out) :: result
  integer :: ipar(2)
  double precision :: dm, vr, contact(3), gap(3), ramp, poly3
  logical :: errflg
  ipar(1) = nint(par(9))
  ipar(2) = nint(par(10))
  call sysfnc('DM', ipar, 2, dm, errflg)
  call sysfnc('VR', ipar, 2, vr, errflg)
  call impact(dm, vr, par(1), par(2), par(3), par(4), par(5), 0, contact, errflg)
  call errmes(errflg, 'IMPACT failed', id, 'STOP')
  call step(time, 0d0, 0d0, 1d0, 2d0, 0, ramp, errflg)
  call errmes(errflg, 'STEP failed', id, 'STOP')
  call poly(dm, 1d0, par(6), 3, 0, poly3, errflg)
  call errmes(errflg, 'POLY failed', id, 'STOP')
  call bistop(dm, vr, 0.5d0, 1.5d0, 1d4, 1.5d0, 10d0, 0.01d0, 0, gap, errflg)
  call errmes(errflg, 'BISTOP failed', id, 'STOP')
  result = contact(1) + ramp + poly3 + gap(1)
end subroutine utilforce

! An SFOSUB whose spring constants come from ARRAY/PAR(1) with GTARAY: k, c, L, I, J.
subroutine arrayspring(id, time, par, npar, dflag, iflag, result)
  implicit none
  integer, intent(in) :: id, npar
  double precision, intent(in) :: time, par(*)
  logical, intent(in) :: dflag, iflag
  double precision, intent(out) :: result
  double precision :: values(16), dm, vr
  integer :: number, istat, ipar(2)
  logical :: errflg
  call gtaray(nint(par(1)), values, number, istat)
  call errmes(istat /= 0 .or. number /= 5, 'ARRAY of k, c, L, I, J expected', id, 'STOP')
  ipar(1) = nint(values(4))
  ipar(2) = nint(values(5))
  call sysfnc('DM', ipar, 2, dm, errflg)
  call sysfnc('VR', ipar, 2, vr, errflg)
  result = -values(1)*(dm - values(3)) - values(2)*vr
end subroutine arrayspring
