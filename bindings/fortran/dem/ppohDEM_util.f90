!! ppohDEM_util (DEM): the original ppOpen-APPL/DEM module, for programs written against it
!! (sample_main01.f90). Same name, derived types, field names and kinds as the original
!! (ppohDEM, Copyright (c) 2014 JAMSTEC, MIT licence; examples/ppohDEM_util.f90, copied below
!! with blank lines removed); particles and objects also hold a handle to ppohdem's C API, and
!! fileinfo and parameters a flag saying their subroutine has run. The subroutines are external,
!! as in the original: ppohdem_dem_stages.f90. docs/fortran.md.
module ppohDEM_util
    use, intrinsic :: iso_c_binding, only: c_ptr, c_null_ptr, c_associated, c_int, c_char, c_null_char, &
                                           c_f_pointer
    implicit none
    public
    private :: c_ptr, c_null_ptr, c_associated, c_int, c_char, c_null_char, c_f_pointer

    ! ppohDEM_precision.inc
    integer, parameter   ::  kint  = 4
    integer, parameter   ::  kreal = 8
    integer, parameter   ::  ppohDEM_name_length = 80
    real(4), parameter   ::  FLT_MAX=+3.402823E+38
    real(4), parameter   ::  FLT_MIN=-3.402823E+38
    real(8), parameter   ::  DBL_MAX=+1.79769313486231D+308
    real(8), parameter   ::  DBL_MIN=-1.79769313486231D+308

    !!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!
    ! fundamental struct
    type ppohDEM_ivec3
        integer(kind=kint) :: x,y,z
    end type
    type ppohDEM_rvec3
        real(kind=kreal) :: x,y,z
    end type
    type ppohDEM_rvec4
        real(kind=kreal) :: x,y,z,w
    end type
    type ppohDEM_ivec2
        integer(kind=kint) :: x,y
    end type
    type ppohDEM_rvec2
        real(kind=kreal) :: x,y
    end type
    type ppohDEM_rvec6
        real(kind=kreal) :: x,y,z
        real(kind=kreal) :: vx,vy,vz
    end type
    type ppohDEM_pvec2
        real(kind=kreal) :: theta,phi
    end type
    type ppohDEM_rtens3
        real(kind=kreal) :: xx,xy,xz
        real(kind=kreal) :: yx,yy,yz
        real(kind=kreal) :: zx,zy,zz
    end type
    type ppohDEM_clist
        integer(kind=kint) :: n
        integer(kind=kint), pointer :: pid(:)
        type(ppohDEM_rvec3), pointer :: tforce(:)
        type(ppohDEM_rvec3), pointer :: dn(:)
    end type
    !!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!
    ! physical variables
    type ppohDEM_particles
        integer(kind=kint) :: n
        real(kind=kreal), pointer :: radius(:)
        type(ppohDEM_rvec3), pointer :: pos(:)
        type(ppohDEM_rvec3), pointer :: vel(:)
        type(ppohDEM_rvec3), pointer :: force(:)
        type(ppohDEM_rvec3), pointer :: omega(:)
        type(ppohDEM_rvec3), pointer :: rforce(:)
        integer(kind=kint), pointer :: cellindex(:)
        integer(kind=kint), pointer :: newtoorig(:)
        type(ppohDEM_clist), pointer :: contact_list(:)
        type(ppohDEM_clist), pointer :: contact_list_wall(:)
        type(c_ptr) :: ppohdem_handle = c_null_ptr   ! set by ppohDEM_pre
    end type
    type ppohDEM_cells
        integer(kind=kint) :: n
        type(ppohDEM_rvec3) :: cellsize
        type(ppohDEM_ivec3) :: cellnum
        integer(kind=kint), pointer :: nei_cellindex(:)
        integer(kind=kint), pointer :: start_partindex(:)
        integer(kind=kint), pointer :: end_partindex(:)
    end type
    type ppohDEM_walls
        integer(kind=kint) :: n
        type(ppohDEM_rvec3), pointer :: point(:)
        type(ppohDEM_rvec3), pointer :: nvec(:)
    end type
    type ppohDEM_objects
        integer(kind=kint) :: gn
        type(ppohDEM_ivec3) :: gridnum
        type(ppohDEM_rvec3) :: gridsize
        real(kind=kreal), pointer :: distance(:)
        real(kind=kreal), pointer :: scaled_distance(:)
        type(ppohDEM_rvec3) :: vel
        type(ppohDEM_rvec4) :: omega
        type(ppohDEM_rvec3) :: centroid
        type(ppohDEM_ivec3) :: winstart
        type(ppohDEM_ivec3) :: winend
        type(ppohDEM_rvec3) :: winstart_r
        type(ppohDEM_rvec3) :: winend_r
        type(ppohDEM_rvec3) :: winmin_r
        type(ppohDEM_rvec3) :: winmax_r
        real(kind=kreal), pointer :: read_distance_3D(:,:,:)
        type(ppohDEM_rvec3), pointer :: winpos_3D(:,:,:) ! window position
        type(ppohDEM_rvec3), pointer :: move_3D(:,:,:)
        type(ppohDEM_rvec3), pointer :: mesh_v1(:) ! mesh
        type(ppohDEM_rvec3), pointer :: mesh_v2(:) ! mesh
        type(ppohDEM_rvec3), pointer :: mesh_v3(:) ! mesh
        integer(kind=kint) :: n_mesh
        type(c_ptr) :: ppohdem_handle = c_null_ptr   ! set by ppohDEM_pre
    end type
    type ppohDEM_counter
        integer(kind=kint) :: itime
        real(kind=kreal) :: rtime
        integer(kind=kint) :: file_index
        real(kind=kreal) :: pos_accum
    end type
    !!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!
    ! file information
    type ppohDEM_fileinfo
        integer(kind=kint) :: func
        character(len=ppohDEM_name_length):: input_filename
        character(len=ppohDEM_name_length):: output_filename
        character(len=ppohDEM_name_length):: input_params_filename
        integer(kind=kint) :: ppohdem_set = 0   ! 1 after ppohDEM_loadfileinfo
    end type ppohDEM_fileinfo
    type ppohDEM_comminfo
        integer(kind=kint) myrank
        integer(kind=kint) nprocs
    end type ppohDEM_comminfo
    !!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!
    ! parameters
    type ppohDEM_parameters
        real(kind=kreal) :: Tstep,Tfin
        integer(kind=kint) :: Dstep,Dfin
        integer(kind=kint) :: Pnum  !!!!  Global parameters !!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!
        type(ppohDEM_rvec3) :: L
        type(ppohDEM_ivec3) :: Cn
        real(kind=kreal) :: Pi
        real(kind=kreal) :: Radius
        real(kind=kreal) :: MaxRadius
        real(kind=kreal) :: Mass
        real(kind=kreal) :: Im
        real(kind=kreal) :: Kn,Kt,En,Et
        real(kind=kreal) :: Fric_const
        real(kind=kreal) :: Gravity
        integer(kind=kint) :: Size_contact_list
        integer(kind=kint) :: Size_contact_list_wall
        real(kind=kreal) :: Wall_decay
        type(ppohDEM_ivec3) :: Obj_n  !!!! object !!!!!!!!!!!!!!!!!!
        real(kind=kreal) :: Obj_Kn,Obj_En
        type(ppohDEM_ivec3) :: winstart
        type(ppohDEM_rvec3) :: vel !vel
        type(ppohDEM_rvec4) :: omega !omega
        type(ppohDEM_rvec3) :: centroid !centroid
        integer(kind=kint) :: ppohdem_set = 0   ! 1 after ppohDEM_setparameters
    end type
    !!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!

    ! Steps after which ppohDEM_dataout writes fullprec/state_stepNNNNNN.dat (env PPOHDEM_STATE_DUMPS).
    integer(kind=kint), allocatable :: ppohdem_binding_dump_steps(:)

contains

    !> Stops the program with the C API's message if status is not PPOHDEM_OK (0).
    subroutine ppohdem_binding_check(status, where)
        integer(c_int), intent(in) :: status
        character(len=*), intent(in) :: where
        if (status /= 0) then
            write (0,'(a)') 'ppohDEM-Error in ' // where // ': ' // ppohdem_binding_last_error()
            stop 1
        endif
    end subroutine

    !> Stops the program with a message if the handle was never set (a stage called too early).
    subroutine ppohdem_binding_require(handle, where, prerequisite)
        type(c_ptr), intent(in) :: handle
        character(len=*), intent(in) :: where, prerequisite
        if (.not. c_associated(handle)) then
            write (0,'(a)') 'ppohDEM-Error: ' // where // ' called before ' // prerequisite
            stop 1
        endif
    end subroutine

    !> A Fortran string, trailing blanks removed, as a NUL-terminated C string.
    function ppohdem_binding_cstr(text) result(c)
        character(len=*), intent(in) :: text
        character(kind=c_char, len=len_trim(text)+1) :: c
        c = trim(text) // c_null_char
    end function

    function ppohdem_binding_last_error() result(message)
        use ppohdem_c_interface, only: ppohdem_last_error
        character(len=:), allocatable :: message
        character(kind=c_char), pointer :: chars(:)
        integer :: n
        call c_f_pointer(ppohdem_last_error(), chars, [4096])
        n = 0
        do while (n < 4096)
            if (chars(n+1) == c_null_char) exit
            n = n + 1
        enddo
        allocate(character(len=n) :: message)
        message = transfer(chars(1:n), message)
    end function

end module ppohDEM_util
