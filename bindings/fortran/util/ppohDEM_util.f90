!! ppohDEM_util (DEM-Util): the original ppOpen-APPL/DEM-Util module, for programs written
!! against it (sample_DEMutil.f90). Same name, derived types, field names and kinds, MPI
!! variables (nprocs, myrank, ierr) and parameters as the original
!! (ppohDEM, Copyright (c) 2014 JAMSTEC, MIT licence; utils/ppohDEM_util.f90); each type that
!! carries the pipeline also holds a handle to ppohdem's C API (ppohdem_handle).
!! The subroutines are external, as in the original: ppohdem_util_stages.f90.
!! docs/fortran.md.
module ppohDEM_util
    use, intrinsic :: iso_c_binding, only: c_ptr, c_null_ptr, c_associated, c_int, c_char, c_null_char, &
                                           c_f_pointer
    implicit none
    public
    private :: c_ptr, c_null_ptr, c_associated, c_int, c_char, c_null_char, c_f_pointer
    include 'mpif.h'

    ! ppohDEM_precision.inc
    integer, parameter   ::  kint  = 4
    integer, parameter   ::  kreal = 8
    integer, parameter   ::  ppohDEM_name_length = 80
    real(4), parameter   ::  FLT_MAX=+3.402823E+38
    real(4), parameter   ::  FLT_MIN=-3.402823E+38
    real(8), parameter   ::  DBL_MAX=+1.79769313486231D+308
    real(8), parameter   ::  DBL_MIN=-1.79769313486231D+308

    integer(kind=kint), parameter :: MAX_MESH=220000
    integer(kind=kint), parameter :: MAX_FACET_CROSSLIST=200
    integer(kind=kint), parameter :: MAX_TEMPLATE=256
    integer(kind=kint), parameter :: HPARAMS_ITERATE = 200

    ! Variables for MPI (the program sets nprocs and myrank)
    integer(kind=kint) :: nprocs = 1, myrank = 0, ierr = 0
    integer(kind=kint) :: quotient, remainder
    integer(kind=kint) :: i_x_start, i_x_end
    integer(kind=kint) :: loop_x_start, loop_x_end

    type ppohDEM_vec3
        real(kind=kreal) :: x,y,z
    end type

    type ppohDEM_rvec3
        real(kind=kreal) :: x,y,z
    end type

    type ppohDEM_minmax
        real(kind=kreal) :: min
        real(kind=kreal) :: max
    end type

    type ppohDEM_fileinfo
        integer(kind=kint) :: func
        character(len=ppohDEM_name_length):: input_filename
        character(len=ppohDEM_name_length):: input_filename2
        character(len=ppohDEM_name_length):: output_filename
        character(len=ppohDEM_name_length):: template_filename
        integer(kind=kint) :: gridX,gridY,gridZ
        type(ppohDEM_vec3) ::object_L, object_size, object_origin
        type(c_ptr) :: ppohdem_handle = c_null_ptr   ! set by ppohDEM_loadfileinfo
    end type ppohDEM_fileinfo

    type ppohDEM_single_mesh
        type(ppohDEM_vec3) :: v1,v2,v3
        type(ppohDEM_minmax) :: x,y,z
    end type

    type ppohDEM_mesh
        integer :: n = 0
        type(ppohDEM_single_mesh),pointer :: mesh(:) => null()
        real(kind=kreal) :: Xmin, Xmax
        real(kind=kreal) :: Ymin, Ymax
        real(kind=kreal) :: Zmin, Zmax
        type(c_ptr) :: ppohdem_handle = c_null_ptr   ! set by ppohDEM_v_pre
    end type

    type ppohDEM_gridco
        real(kind=kreal),pointer :: x(:) => null(), y(:) => null(), z(:) => null()
    end type

    type ppohDEM_voxel
        integer(kind=kint) :: gridX,gridY,gridZ
        integer(kind=kint),pointer :: value_3D(:,:,:) => null()      ! 1 where the voxelisation says inside
        real(kind=kreal),pointer :: distance_3D(:,:,:) => null()     ! the field after the last stage [m]
        integer(kind=kint),pointer :: calculated_3D(:,:,:) => null() ! not filled (internal to ppohdem)
        real(kind=kreal) :: Lx, Ly, Lz
        real(kind=kreal) :: W
        real(kind=kreal) :: W2
        integer(kind=kint) :: cellX, cellY, cellZ
        real(kind=kreal) :: sizeX, sizeY, sizeZ
        real(kind=kreal) :: posX, posY, posZ
        type(c_ptr) :: ppohdem_handle = c_null_ptr   ! set by ppohDEM_v_pre
    end type

    type ppohDEM_particle_template
        integer(kind=kint) :: n
        type(ppohDEM_vec3),pointer :: p(:)
    end type

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
