! Error path: a DEM-Util stage before its prerequisite must stop with a message, not crash.
program util_before_pre
    use ppohDEM_util
    implicit none
    type(ppohDEM_fileinfo) :: file_info
    type(ppohDEM_mesh) :: meshXYZ
    type(ppohDEM_voxel) :: voxel
    type(ppohDEM_gridco) :: gridco
    call MPI_INIT(ierr)
    call ppohDEM_v_makevoxel(file_info, meshXYZ, voxel, gridco)
    call MPI_FINALIZE(ierr)
end program
